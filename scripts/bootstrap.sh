#!/usr/bin/env bash
# Make a fresh Debian 12 machine ready: the Debian packages the project needs
# (python3-venv, yade, chromium) and a virtual environment with the pinned Python packages
# (versions: constraints.txt; ranges and groups: pyproject.toml).
# Idempotent: reruns only install what is missing or what pyproject.toml or constraints.txt changed.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
PYTHON=${PYTHON:-python3}

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }
apt_updated=0
apt_install() {
    if [ "$apt_updated" = 0 ]; then
        echo "bootstrap: apt-get update" >&2
        as_root apt-get update -qq
        apt_updated=1
    fi
    echo "bootstrap: apt-get install $*" >&2
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
}

if ! command -v "$PYTHON" >/dev/null; then apt_install python3; fi
if ! "$PYTHON" -c 'import venv, ensurepip' 2>/dev/null; then apt_install python3-venv; fi
if ! command -v yade >/dev/null; then apt_install yade; fi
# headless Chromium: the test suite opens the report pages in a real browser
if ! command -v chromium >/dev/null; then apt_install chromium; fi

stamp="$VENV/.installed"
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ] || [ constraints.txt -nt "$stamp" ]; then
    if [ ! -x "$VENV/bin/python" ]; then
        echo "bootstrap: creating $VENV" >&2
        "$PYTHON" -m venv "$VENV"
    fi
    echo "bootstrap: installing the pinned packages into $VENV" >&2
    "$VENV/bin/python" -m pip install -q --upgrade pip
    "$VENV/bin/python" -m pip install -q -c constraints.txt -e ".[test]"
    # LMGC90, the second DEM engine: listed in pyproject.toml [tool.masonry-limit], pinned in
    # constraints.txt, installed without its declared dependencies (a Qt viewer the project
    # does not use). A name without an exact pin in constraints.txt stops here.
    nodeps=$("$VENV/bin/python" - <<'PY'
import re, sys, tomllib
names = tomllib.load(open("pyproject.toml", "rb"))["tool"]["masonry-limit"]["no-deps"]
pins = {m[1].lower().replace("_", "-") for m in re.finditer(r"^([A-Za-z0-9_.-]+)==\S+", open("constraints.txt").read(), re.M)}
unpinned = [n for n in names if n.lower().replace("_", "-") not in pins]
if unpinned:
    sys.exit(f"bootstrap: no exact pin in constraints.txt for {', '.join(unpinned)}")
print(" ".join(names))
PY
)
    if "$VENV/bin/python" -m pip install -q -c constraints.txt --no-deps $nodeps; then
        touch "$stamp"
    else  # no stamp: the next make tries again
        echo "bootstrap: WARNING: could not install $nodeps: the LMGC90 engine will report 'failed'" >&2
    fi
fi
