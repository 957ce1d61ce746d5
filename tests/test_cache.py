"""reports/cache.py: a cache entry is found again only for the same scene content, stage options
and code (fingerprint of the stage's packages and pyproject.toml)."""
import json
import shutil

import pytest

from reports import cache as C

SCENE = C.ROOT / "scenes" / "catalog" / "block-rocking-2d.json"
OPTS = {"method": "auto", "solver": "auto"}


def key_of(path, opts=OPTS, stage="la"):
    """The key as reports/validate.plan makes it: from the parsed scene file."""
    return C.key(stage, json.loads(path.read_text()), opts)


@pytest.fixture
def scene(tmp_path):
    p = tmp_path / "scene.json"
    shutil.copy(SCENE, p)
    return p


def test_unchanged_scene_and_options_hit(scene, tmp_path):
    """Same file, same options: the same key, and get returns what put stored (NaN as null)."""
    cache = C.Cache(tmp_path / "cache")
    k = key_of(scene)
    assert cache.get("la", "s", k) is None
    cache.put("la", "s", k, {"lp": {"alpha": 0.3, "t": float("nan")}})
    assert key_of(scene) == k
    assert cache.get("la", "s", key_of(scene)) == {"lp": {"alpha": 0.3, "t": None}}


def test_reformatted_scene_file_hits(scene):
    """The key hashes canonical JSON: other indentation and key order in the file give the same key."""
    k = key_of(scene)
    d = json.loads(scene.read_text())
    scene.write_text(json.dumps(dict(reversed(list(d.items()))), indent=7))
    assert key_of(scene) == k


@pytest.mark.parametrize("change", ["friction", "block moved 1e-12 m", "block id", "live load", "meta"])
def test_changed_scene_file_misses(scene, tmp_path, change):
    """Any change of the file's content (even 1e-12 m, or only meta) gives another key: a miss."""
    cache = C.Cache(tmp_path / "cache")
    k = key_of(scene)
    cache.put("la", "s", k, {"lp": {"alpha": 0.3}})
    d = json.loads(scene.read_text())
    if change == "friction":
        d["friction"] = d["friction"] + 0.01
    elif change == "block moved 1e-12 m":
        d["blocks"][1]["box"]["center"][0] += 1e-12
    elif change == "block id":
        d["blocks"][1]["id"] += "x"
    elif change == "live load":
        d["loads"]["live"][0]["direction"] = [-1.0, 0.0]
    else:
        d["meta"] = {"title": "x"}
    scene.write_text(json.dumps(d))
    k2 = key_of(scene)
    assert k2 != k
    assert cache.get("la", "s", k2) is None


def test_changed_options_or_stage_miss(scene, tmp_path):
    """Other option values, an extra option or another stage: another key. The order of the option
    keys does not matter."""
    k = key_of(scene)
    assert key_of(scene, {"solver": "auto", "method": "auto"}) == k
    others = [key_of(scene, {"method": "lp", "solver": "auto"}), key_of(scene, dict(OPTS, global_check=True)),
              key_of(scene, {"method": "auto"}), key_of(scene, OPTS, stage="cone")]
    assert len({k, *others}) == 1 + len(others)


def test_limits_and_measured_costs_keep_the_key(scene):
    """A stage's limits (timeout_s, cpu_limit_s) and the scene's measured cost (meta.dem.cost_s)
    decide no result: changing them keeps the key; a knob in meta.dem changes it."""
    opts = dict(OPTS, timeout_s=100.0, cpu_limit_s=50.0)
    k = key_of(scene, opts)
    assert key_of(scene, dict(opts, timeout_s=900.0, cpu_limit_s=300.0)) == k == key_of(scene, OPTS)
    d = json.loads(scene.read_text())
    d.setdefault("meta", {})["dem"] = {"cost_s": 10.0}
    k = C.key("la", d, opts)
    d["meta"]["dem"] = {"cost_s": 426.0}
    assert C.key("la", d, opts) == k
    d["meta"]["dem"] = {"cost_s": 426.0, "knobs": {"eps": [1e-5]}}
    assert C.key("la", d, opts) != k


def test_failed_results_and_broken_files_never_hit(scene, tmp_path):
    """put_failed keeps the result outside the cache (get misses); a half-written entry is a miss."""
    cache = C.Cache(tmp_path / "cache")
    k = key_of(scene)
    kept = cache.put_failed("la", "s", k, {"lp": {"status": "failed", "reason": "x"}})
    assert json.loads(kept.read_text())["lp"]["reason"] == "x"
    assert cache.get("la", "s", k) is None
    p = cache.path("la", "s", k)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text('{"lp": {"alpha": 0.')
    assert cache.get("la", "s", k) is None


@pytest.fixture
def fake_root(tmp_path, monkeypatch):
    """A source tree with packages limit/ and dem_validation/ and a pyproject.toml as reports.cache.ROOT
    (the lru_cache of code_fingerprint cleared before and after)."""
    root = tmp_path / "root"
    for rel, text in {"limit/__init__.py": "", "limit/solve/lp.py": "A = 1\n", "limit/schema.json": "{}",
                      "limit/notes.md": "x", "dem_validation/run.py": "B = 1\n", "dem_validation/engines/yade/main.py": "Y = 1\n",
                      "dem_validation/engines/lmgc90/main.py": "L = 1\n", "pyproject.toml": "[project]\n"}.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)
    monkeypatch.setattr(C, "ROOT", root)
    C.code_fingerprint.cache_clear()
    yield root
    C.code_fingerprint.cache_clear()


def fingerprints():
    C.code_fingerprint.cache_clear()  # a new process, as each validate run is
    return C.code_fingerprint("la"), C.code_fingerprint("dem")


@pytest.mark.parametrize("edit, yade_changes, lmgc_changes", [
    ("dem_validation/run.py", True, True),
    ("dem_validation/engines/yade/main.py", True, False),
    ("dem_validation/engines/lmgc90/main.py", False, True),
])
def test_engine_stamps(fake_root, edit, yade_changes, lmgc_changes):
    """An engine's own folder decides only that engine's stage: YADE's ("dem") and LMGC90's ("lmgc")
    fingerprints both follow the shared dem_validation/ code, each only its own adapter."""
    C.code_fingerprint.cache_clear()
    before = C.code_fingerprint("dem"), C.code_fingerprint("lmgc")
    p = fake_root / edit
    p.write_text(p.read_text() + "# changed\n")
    C.code_fingerprint.cache_clear()
    after = C.code_fingerprint("dem"), C.code_fingerprint("lmgc")
    assert (after[0] != before[0], after[1] != before[1]) == (yade_changes, lmgc_changes)


@pytest.mark.parametrize("edit, la_changes, dem_changes", [
    ("limit/solve/lp.py", True, True),
    ("limit/schema.json", True, True),
    ("limit/new.py", True, True),
    ("pyproject.toml", True, True),
    ("constraints.txt", True, True),
    ("dem_validation/run.py", False, True),
    ("limit/notes.md", False, False),
    ("limit/__pycache__/lp.cpython-312.pyc", False, False),
    ("limit/__pycache__/stale.py", False, False),
])
def test_code_stamp(fake_root, scene, edit, la_changes, dem_changes):
    """A changed .py or .json file of a stage's packages, or pyproject.toml or constraints.txt (the pinned versions),
    changes that stage's fingerprint and so its keys (a miss); other files change nothing (a hit).
    la runs limit/ only, dem also dem_validation/."""
    la0, dem0 = fingerprints()
    k0 = key_of(scene)
    assert fingerprints() == (la0, dem0) and key_of(scene) == k0  # unchanged code: a hit
    p = fake_root / edit
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text((p.read_text() if p.exists() else "") + "# changed\n")
    la1, dem1 = fingerprints()
    assert (la1 != la0, dem1 != dem0) == (la_changes, dem_changes)
    assert (key_of(scene) != k0) == la_changes
