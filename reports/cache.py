"""Results cached by scene content and code version, written atomically.

A stage result (``la``: limit analysis, ``dem``: DEM pushover) of a scene is
stored as ``<root>/<stage>/<scene name>-<key>.json`` where the key hashes the
scene file's canonical JSON, the stage options and the fingerprint of the code
the stage runs (every source file of the packages involved, pyproject.toml and
the pinned versions in constraints.txt). An unchanged scene is not recomputed; an
interrupted run resumes from what is stored; a half-written file is never
seen (write to a temporary file, then rename).

A failed stage result is not a cache entry (the next run tries the stage again)
but is kept whole, with its reason and histories, as
``<root>/failed/<stage>/<scene name>-<key>-<UTC time>.json`` for diagnosis:
a failure that does not come back on the rerun is not lost.
"""
from __future__ import annotations

import datetime
import hashlib
import json
from functools import lru_cache
from pathlib import Path

from limit import jsonio
ROOT = Path(__file__).resolve().parents[1]
DEFAULT_DIR = ROOT / ".cache" / "results"
#: packages whose source decides each stage's result
STAGE_CODE = {"la": ("limit",), "cone": ("limit",), "sweep": ("limit",), "solve": ("limit",), "dem": ("limit", "dem_validation"), "lmgc": ("limit", "dem_validation")}
#: folders of those packages that one DEM stage never runs: each engine's own adapter and side scripts
#: (a change to LMGC90's time step does not recompute YADE's stages, and the other way round)
STAGE_SKIPS = {"dem": ("dem_validation/engines/lmgc90",), "lmgc": ("dem_validation/engines/yade",)}


@lru_cache(maxsize=None)
def code_fingerprint(stage: str) -> str:
    h = hashlib.sha256()
    skips = tuple(ROOT / s for s in STAGE_SKIPS.get(stage, ()))
    for pkg in STAGE_CODE[stage]:
        for p in sorted((ROOT / pkg).rglob("*")):
            skipped = any(p.is_relative_to(s) for s in skips)
            if p.suffix in (".py", ".json") and "__pycache__" not in p.parts and not skipped:
                h.update(str(p.relative_to(ROOT)).encode())
                h.update(p.read_bytes())
    for name in ("pyproject.toml", "constraints.txt"):  # the version ranges, the pinned versions
        if (ROOT / name).exists():
            h.update((ROOT / name).read_bytes())
    return h.hexdigest()


#: stage options that decide no result (a result that came back did not reach its limits), and the
#: scene's per-stage entry that only orders the run (its measured cost), both left out of the key
NOT_IN_KEY = ("timeout_s", "cpu_limit_s")
META_NOT_IN_KEY = ("cost_s",)


def _decisive(scene_data: dict, options: dict) -> tuple[dict, dict]:
    """The scene and options without what decides no result (:data:`NOT_IN_KEY`)."""
    opts = {k: v for k, v in options.items() if k not in NOT_IN_KEY}
    meta = scene_data.get("meta")
    if isinstance(meta, dict):
        meta = {st: ({k: v for k, v in m.items() if k not in META_NOT_IN_KEY} if isinstance(m, dict) else m)
                for st, m in meta.items()}
        scene_data = {**scene_data, "meta": meta}
    return scene_data, opts


def key(stage: str, scene_data: dict, options: dict) -> str:
    scene_data, options = _decisive(scene_data, options)
    payload = json.dumps({"stage": stage, "scene": scene_data, "options": options}, sort_keys=True,
                         separators=(",", ":"), default=str)
    h = hashlib.sha256(payload.encode())
    h.update(code_fingerprint(stage).encode())
    return h.hexdigest()[:20]


class Cache:
    def __init__(self, root: Path | str = DEFAULT_DIR):
        self.root = Path(root)

    def path(self, stage: str, name: str, k: str) -> Path:
        return self.root / stage / f"{name}-{k}.json"

    def get(self, stage: str, name: str, k: str) -> dict | None:
        p = self.path(stage, name, k)
        try:
            return json.loads(p.read_text())
        except (FileNotFoundError, json.JSONDecodeError):
            return None

    def put_failed(self, stage: str, name: str, k: str, result: dict) -> Path:
        """Keep a failed result (never read back as a cache hit); returns its path."""
        stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%S%fZ")
        p = self.root / "failed" / stage / f"{name}-{k}-{stamp}.json"
        jsonio.write_json(p, result)
        return p

    def put(self, stage: str, name: str, k: str, result: dict) -> Path:
        p = self.path(stage, name, k)
        jsonio.write_json(p, result)
        return p
