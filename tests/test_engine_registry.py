"""dem_validation.engines: the engines behind one interface (no YADE, no LMGC90 run).

The registry finds each engine and refuses an unknown one by naming the known ones; no code
outside dem_validation/engines/ asks which engine it has (``engine == ...``); a DemResult
writes back exactly the dict of today's shape it was read from, for every status, and the
engines' own builders give today's keys in today's order."""
import re
from pathlib import Path
from types import SimpleNamespace

import pytest

from dem_validation import engines
from dem_validation.engines import DemResult, Status

ROOT = Path(__file__).resolve().parent.parent
#: the project's code (tests excepted: they may look at a result's engine)
SOURCES = ("dem_validation", "reports", "limit", "bench", "scenes", "scripts", "examples")
#: a comparison with an engine: ``engine ==``, ``.get("engine") !=``, ``== "lmgc90"``, ``"yade" ==``
BRANCH = re.compile(r"""\bengine\s*[!=]=|\bengine["']\)\s*[!=]=|[!=]=\s*["'](?:yade|lmgc90)["']|"""
                    r"""["'](?:yade|lmgc90)["']\s*[!=]=""")


@pytest.mark.parametrize("name, label, rigid, entry", [("yade", "YADE", False, "yade_main.py"),
                                                       ("lmgc90", "LMGC90", True, "lmgc_main.py")])
def test_get_finds_each_engine(name, label, rigid, entry):
    eng = engines.get(name)
    assert isinstance(eng, engines.Engine)
    assert (eng.name, eng.label, eng.rigid, eng.entry) == (name, label, rigid, entry)
    assert entry in eng.side_files
    for f in eng.side_files:  # the runner copies these into the engine's work directory
        assert (eng.side_dir / f).is_file(), f
    assert eng.side_dir == ROOT / "dem_validation" / "engines" / name
    assert name in engines.names()


def test_the_default_engine_is_yade_and_a_result_without_engine_is_its():
    assert engines.DEFAULT == "yade" and engines.names()[0] == "yade"
    assert engines.of_result({"status": "collapsed"}).name == "yade"
    assert engines.of_result({"status": "collapsed", "engine": "lmgc90"}).name == "lmgc90"


def test_an_unknown_engine_is_refused_by_name():
    with pytest.raises(ValueError, match=r"expected one of yade, lmgc90, got 'abaqus'"):
        engines.get("abaqus")
    from dem_validation import run_scene

    with pytest.raises(ValueError, match="'abaqus'"):  # before the scene is read
        run_scene("no-such-scene.json", engine="abaqus")
    from dem_validation.runner import run_job

    with pytest.raises(ValueError, match="'abaqus'"):
        run_job({}, engine="abaqus")


def test_knobs_are_each_engines_own():
    assert engines.get("yade").knobs({}, "vertex")["eps"] == [1e-5, 2.5e-6]
    assert engines.get("yade").knobs({}, "polyhedra")["eps"] == [1e-4, 1e-5]
    assert engines.get("lmgc90").knobs({"dt": 2e-3})["dt"] == 2e-3
    with pytest.raises(ValueError, match="unknown DEM knob"):
        engines.get("yade").knobs({"dt": 1e-3})
    with pytest.raises(ValueError, match="unknown LMGC90 knob"):
        engines.get("lmgc90").knobs({"damping": 0.5})


def test_what_each_block_model_carries():
    y, lm = engines.get("yade"), engines.get("lmgc90")
    assert y.models("vertex") == engines.Models(ties=True, bonds=True, compound=True)
    assert y.models("polyhedra") == engines.Models(ties=False, bonds=False, compound=False)
    assert lm.models() == engines.Models(ties=False, bonds=False, compound=True)


def test_the_branch_pattern_sees_the_comparisons_it_is_for():
    for line in ('if engine == "yade":', 'p = a if args.engine == "lmgc90" else b',
                 'if (lmgc or {}).get("engine") == "lmgc90" else', 'x = "lmgc90" != name',
                 'if dem.get("engine") != "yade":'):
        assert BRANCH.search(line), line
    for line in ('res = {"engine": "lmgc90"}', 'eng = engines.get(engine)', 'engine = "yade"'):
        assert not BRANCH.search(line), line


def test_no_engine_branches_outside_the_registry():
    own = ROOT / "dem_validation" / "engines"
    files = [p for d in SOURCES if (ROOT / d).is_dir() for p in (ROOT / d).rglob("*.py")]
    assert any(p.name == "cli.py" for p in files) and any(p.name == "plots.py" for p in files)
    found = [f"{p.relative_to(ROOT)}:{k}: {line.strip()}" for p in files if own not in p.parents
             for k, line in enumerate(p.read_text().splitlines(), 1) if BRANCH.search(line)]
    assert not found, "engine branches outside dem_validation/engines/:\n" + "\n".join(found)


# dem dicts of today's shape, one per status (and engine), written out by hand
RESULTS = {
    "yade collapsed": {
        "status": "collapsed", "alpha": 0.3005, "alpha_uncertainty": 0.0014,
        "extrapolation": {"alpha_rigid": 0.3005, "uncertainty": 0.0014, "correction": 0.001, "method": "richardson"},
        "displacement": {"b": [0.0, 0.0, -1e-3]}, "note": "a note",
        "runs": [{"eps": 1e-5, "status": "collapsed", "alpha": 0.2995}, {"eps": 2.5e-6, "status": "collapsed",
                                                                          "alpha": 0.3002}],
        "history": [{"eps": 1e-5, "phase": "load", "alpha": 0.1, "outcome": "stable"}], "steps": 16319,
        "cpu_s": 2.5, "fixed_addresses": True, "penetration_ratio": 0.05, "runs_used": [1e-5, 2.5e-6],
        "time_s": 3.2, "params": {"eps": [1e-5, 2.5e-6]}, "contact": "vertex"},
    "yade dead-load collapse": {
        "status": "collapsed", "alpha": None, "dead_load_collapse": True,
        "note": "collapses under the dead load alone (alpha <= 0)", "displacement": None, "runs": [],
        "history": [], "steps": 10, "runs_used": [1e-5], "time_s": 1.0, "params": {}, "contact": "polyhedra"},
    "yade stable": {
        "status": "stable", "alpha": None, "note": "no free block: nothing can move", "time_s": 0.0,
        "params": {"eps": [1e-5]}},
    "yade failed": {
        "status": "failed", "reason": "timed out after 10.0 s (time limit 10 s); YADE was killed",
        "steps_total": 5, "cpu_s": 9.5, "progress": {"phases": [], "last": [{"alpha": 0.1}]}, "time_s": 10.2,
        "params": {}, "contact": "vertex"},
    "lmgc90 collapsed": {
        "status": "collapsed", "alpha": 0.30078, "alpha_uncertainty": 0.00078,
        "runs": [{"eps": 0.0, "status": "collapsed", "alpha": 0.30078, "alpha_lo": 0.3, "alpha_hi": 0.30156,
                  "steps": 1992, "dead_load_collapse": False}],
        "history": [{"phase": "load", "alpha": 0.3, "outcome": "stable", "eps": 0.0}], "steps": 1992,
        "displacement": {"b": [0.0, 0.0, -1e-6]}, "time_s": 2.2, "engine": "lmgc90", "params": {"dt": 1e-3}},
    "lmgc90 skipped": {
        "status": "skipped", "alpha": None, "reason": "LMGC90 cannot model this scene: per-pair friction",
        "time_s": 0.1, "engine": "lmgc90", "params": {"dt": 1e-3}},
    "with a bracket": {
        "status": "collapsed", "alpha": 0.2, "alpha_uncertainty": 0.001, "runs": [], "time_s": 1.0,
        "bracket": {"verdict": "suspect", "side": "low"}, "suspect": True},
}


@pytest.mark.parametrize("case", list(RESULTS))
def test_a_result_writes_back_the_dict_it_was_read_from(case):
    d = RESULTS[case]
    r = DemResult.from_dict(d)
    assert r.status is Status(d["status"]) and r.status.value == d["status"]
    assert r.alpha == d.get("alpha")
    out = r.to_dict()
    assert out == d and list(out) == list(d)
    assert "alpha" in out or "alpha" not in d  # an absent key stays absent (a failed result has no alpha)


def test_the_statuses_are_todays_strings():
    assert {s.value for s in Status} == {"collapsed", "stable", "failed", "skipped"}
    with pytest.raises(ValueError):
        DemResult.of("done")


def test_with_updates_like_a_dict():
    r = DemResult.of("skipped", alpha=None, reason="x").with_(time_s=1.0, reason="y", engine="lmgc90")
    assert list(r.to_dict().items()) == [("status", "skipped"), ("alpha", None), ("reason", "y"), ("time_s", 1.0),
                                         ("engine", "lmgc90")]


def test_a_scene_with_nothing_free_gives_the_same_result_shape_in_both_engines():
    scene = SimpleNamespace(free=[])
    assert engines.get("yade").run(scene, engines.get("yade").knobs({"eps": [1e-5]})).to_dict() == {
        "status": "stable", "alpha": None, "note": "no free block: nothing can move", "time_s": 0.0,
        "params": dict(engines.get("yade").knobs({}), eps=[1e-5])}
    lm = engines.get("lmgc90").run(scene, {}).to_dict()
    assert list(lm) == ["status", "alpha", "note", "time_s", "engine", "params"]
    assert (lm["status"], lm["engine"], lm["params"]["dt"]) == ("stable", "lmgc90", 1e-3)


def test_the_engines_assemble_todays_keys_in_todays_order():
    from dem_validation.api import assemble
    from dem_validation.lmgc import assemble_rigid

    run = {"eps": 0.0, "status": "collapsed", "alpha": 0.3, "alpha_lo": 0.29, "alpha_hi": 0.31, "steps": 7,
           "dead_load_collapse": False, "history": [{"phase": "load", "alpha": 0.29, "outcome": "stable"}],
           "displacement": {"b": [1, 2, 3]}}
    dem = assemble_rigid({"status": "done", "runs": [run]})
    assert list(dem) == ["status", "alpha", "alpha_uncertainty", "runs", "history", "steps", "steps_total",
                         "displacement", "dt_converged"]
    assert dem["alpha_uncertainty"] == pytest.approx(0.01) and dem["history"][0]["eps"] == 0.0
    runs = [{"eps": e, "status": "collapsed", "alpha": a, "alpha_lo": a - 1e-3, "alpha_hi": a + 1e-3, "steps": 5,
             "history": [], "displacement": {"b": [0, 0, 1]}} for e, a in ((1e-5, 0.299), (2.5e-6, 0.300))]
    dem = assemble({"status": "done", "runs": runs, "cpu_s": 1.0, "fixed_addresses": True},
                   {"extrapolation_exponent": 1.0, "pen_limit": 0.3})
    assert list(dem) == ["status", "alpha", "alpha_uncertainty", "extrapolation", "displacement", "runs", "history",
                         "steps", "cpu_s", "fixed_addresses", "runs_used"]
    assert dem["status"] == "collapsed" and dem["steps"] == 10 and dem["runs_used"] == [1e-5, 2.5e-6]
    assert assemble({"status": "failed", "reason": "YADE  crashed\n(signal SIGSEGV)", "cpu_s": 2.0}, {}) == {
        "status": "failed", "reason": "YADE crashed (signal SIGSEGV)", "cpu_s": 2.0}


def test_the_summary_line_is_the_engines():
    from dem_validation.cli import summary

    base = {"scene": "s", "n_blocks": 2, "n_free_blocks": 1, "n_interfaces": 1}
    lm = summary(dict(base, dem={"status": "collapsed", "alpha": 0.30078, "alpha_uncertainty": 0.00078,
                                 "engine": "lmgc90", "time_s": 2.2, "steps": 1992}))
    assert "LMGC90 (rigid contacts) collapsed: alpha = 0.30078 +- 0.00078" in lm
    y = summary(dict(base, dem={"status": "collapsed", "alpha": 0.3005, "alpha_uncertainty": 0.0014,
                                "extrapolation": {"method": "richardson"}, "time_s": 3.2, "steps": 16319,
                                "runs": [{"eps": 1e-5, "alpha": 0.29946}, {"eps": 2.5e-6, "alpha": 0.30024}]}))
    assert ("DEM collapsed: alpha = 0.3005 +- 0.0014 (rigid-contact extrapolation of the two stiffest runs "
            "0.29946 (eps 1e-05), 0.30024 (eps 2.5e-06))") in y


def test_a_yade_result_of_one_run_does_not_claim_an_extrapolation():
    from dem_validation.engines.yade import ENGINE

    line = ENGINE.collapse_line({"alpha": 0.56544, "alpha_uncertainty": 0.00099, "extrapolation": {"method": "richardson"},
                                 "runs": [{"eps": 2.5e-6, "alpha": 0.56544}]})
    assert line == "DEM collapsed: alpha = 0.56544 +- 0.00099 (the one run 0.56544 (eps 2.5e-06))"
