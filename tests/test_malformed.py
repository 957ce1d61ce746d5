"""The corpus of malformed scene files (tests/malformed/) through every command.

Each file must give exit status 2 with one line on stderr naming the fault
(the fragment in tests/malformed/expected.json), never a traceback and never a
result file, from ``limit info``, ``limit solve --json`` and
``dem_validation run --json``. In-process for speed; a sample also as real
subprocesses.
"""
import json
from pathlib import Path

import pytest

from dem_validation.cli import main as dem_main
from limit.cli import main as limit_main
from tests.conftest import run_module

CORPUS = Path(__file__).parent / "malformed"
EXPECTED = json.loads((CORPUS / "expected.json").read_text())
COMMANDS = {
    "limit info": lambda f, out: limit_main(["info", str(f), "--json", str(out)]),
    "limit solve": lambda f, out: limit_main(["solve", str(f), "--json", str(out)]),
    "dem_validation run": lambda f, out: dem_main(["run", str(f), "--json", str(out)]),
}


def test_corpus_is_complete():
    files = {p.name for p in CORPUS.glob("*.json")} - {"expected.json"}
    assert files == set(EXPECTED), files ^ set(EXPECTED)
    assert len(files) >= 30


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_malformed_file(name, command, tmp_path, capsys):
    out = tmp_path / "result.json"
    code = COMMANDS[command](CORPUS / name, out)
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert (code, len(lines), "Traceback" in err, EXPECTED[name] in err, out.exists()) == (2, 1, False, True, False), err


@pytest.mark.parametrize("name", ["truncated.json"] + [pytest.param(n, marks=pytest.mark.slow) for n in (  # 4-5 s each
    "nan_coordinate.json", "overlapping_blocks_3d.json", "no_fixed_block.json")])
def test_malformed_subprocess(name, tmp_path):
    out = tmp_path / "r.json"
    for module, args in (("limit", ["solve", CORPUS / name, "--json", out]),
                         ("dem_validation", ["run", CORPUS / name, "--json", out])):
        r = run_module(module, *args, timeout=120)
        assert r.returncode == 2, r.stderr
        assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
        assert EXPECTED[name] in r.stderr
        assert not out.exists()
