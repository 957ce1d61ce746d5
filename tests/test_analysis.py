"""limit.analysis.analyse: a typed :class:`Analysis` whose ``data`` is the result file's content
and nothing else, and the printed summary made from that content alone."""
import dataclasses
import json

import pytest

from limit import jsonio
from limit.analysis import Analysis, analyse
from limit.model.assemble import Assembled
from limit.model.scene import load_scene
from limit.results.summary import format_result
from scenes.catalog import CATALOG_DIR


def _keys(x):
    """Every dict key in x, at any depth."""
    if isinstance(x, dict):
        for k, v in x.items():
            yield k
            yield from _keys(v)
    elif isinstance(x, (list, tuple)):
        for v in x:
            yield from _keys(v)


@pytest.fixture(scope="module")
def tied():
    """block-tied-2d with step 2: a frictional point with ties."""
    return analyse(load_scene(str(CATALOG_DIR / "block-tied-2d.json")), method="nlp")


def test_the_analysis_is_typed_and_its_data_holds_only_the_result(tied):
    a = tied
    assert isinstance(a, Analysis) and isinstance(a.P, Assembled)
    assert a.sol.status == a.data["lp"]["status"] == "optimal" and a.data["nlp"]["status"] == "optimal"
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.data = {}
    portal = analyse(load_scene(str(CATALOG_DIR / "portal-2d.json"))).data  # with a demand: a verdict part
    for d in (a.data, portal):
        assert not [k for k in _keys(d) if str(k).startswith("_")]
        json.loads(jsonio.dumps(d))
    assert "verdict" in portal


def test_the_summary_of_a_result_file_is_that_of_the_fresh_result(tied):
    """The print is a function of the result file's content: the cached file's (a JSON round
    trip) equals the fresh one's, step 2's mechanism and ties included."""
    fresh = format_result(tied.data)
    assert format_result(json.loads(jsonio.dumps(tied.data))) == fresh
    nlp = fresh[fresh.index("NLP"):]
    assert "mechanism (frictional):" in nlp and "ties: rod yields" in nlp


def test_statuses_are_typed_and_read_as_their_strings(tied):
    """A status is a :class:`limit.solve.status.Status`, equal to its string and written as it
    (JSON, f-strings), so a result file reads as with bare strings; the typed result reads a
    file's strings back as members."""
    from limit.api import StepResult
    from limit.solve.status import Status

    s = tied.data["lp"]["status"]
    assert s is Status.OPTIMAL and tied.sol.status is Status.OPTIMAL and tied.data["nlp"]["status"] is Status.OPTIMAL
    assert s == "optimal" and f"{s}" == str(s) == "optimal" and json.dumps({"status": s}) == '{"status": "optimal"}'
    assert StepResult.from_dict({"status": "skipped", "alpha": 0.3}).status is Status.SKIPPED


def test_step2_reports_a_negative_verified_alpha_as_infeasible(monkeypatch):
    """A verified frictional point below zero (beyond tol_gap): the dead load alone collapses the
    assembly, and step 2's own part says so (as the LP's does), so a direct caller sees it too."""
    from limit import step2
    from limit.analysis import solve_lp
    from limit.model.assemble import assemble
    from scenes import builders as B

    real = step2.run

    def negated(*a, **k):  # the real point, its alpha made negative
        r = real(*a, **k)
        return r.replace(alpha=-0.1) if r.ok else r
    monkeypatch.setattr(step2, "run", negated)
    P = assemble(load_scene(B.side_by_side(dim=2, mu=0.5)))
    sol, _, _ = solve_lp(P)
    part = step2.step2(P, sol, method="nlp", global_check=False)
    assert part["status"] == "infeasible" and part["alpha"] == -0.1 and "mechanism" in part


def test_an_unproven_global_minimum_is_reported_as_an_interval():
    """A MILP stopped at its time limit proves only a lower bound: the summary and the report give
    the frictional minimum as [bound, step 2's answer]; a proven optimum or a missing bound gives
    no interval. The numbers are made up here: the test checks the wording, not a solver."""
    from limit.results.summary import global_interval
    from reports.render import scene_summary

    nlp = {"status": "optimal", "alpha": 0.181726, "route": "successive-lp",
           "global": {"status": "time_limit", "alpha": 0.181726, "bound": 0.0421, "time_s": 400.0}}
    assert global_interval(nlp) == (0.0421, 0.181726)
    assert global_interval({**nlp, "global": {**nlp["global"], "bound": -0.5}}) == (0.0, 0.181726)
    assert global_interval({**nlp, "global": {**nlp["global"], "status": "optimal"}}) is None
    assert global_interval({**nlp, "global": {**nlp["global"], "bound": None}}) is None
    assert global_interval({**nlp, "status": "failed", "alpha": None}) is None
    res = {"scene": "s", "dim": 3, "n_free_blocks": 2, "n_interfaces": 3,
           "lp": {"status": "optimal", "alpha": 0.19, "solver": "clarabel", "time_s": 0.1,
                  "model": {"interfaces": 3, "n_slide": 24, "slide_fit": "inscribed"}}, "nlp": nlp}
    assert "the frictional minimum lies in [0.0421, 0.181726]" in format_result(res)
    row = {"lp_alpha": 0.19, "lp_status": "optimal", "lp_reason": "", "lp_time_s": 0.1, "fric_alpha": 0.181726,
           "nlp_status": "optimal", "nlp_reason": "", "nlp_time_s": 5.0, "dim": 2}
    assert any("[0.0421, 0.181726]" in line for line in scene_summary(row, {"nlp": nlp}))
    from reports.render import explain

    row.update(global_status="time_limit", global_alpha=0.181726, global_lo=0.0421, global_hi=0.181726)
    assert any("lies in [0.0421, 0.181726]" in line for line in explain(row))


def test_the_nearby_starts_run_no_global_milp_or_iterative_lp_of_their_own(monkeypatch):
    """``--global`` (and ``--iterative-lp``) check the scene's own frictional problem once. The
    nearby starts (the live load turned by +-5 deg, the mirrored reversed load) only supply
    collapse states to try, so they run neither: each would cost a whole MILP time limit more.
    A 3D stack of three blocks under a body force takes both nearby starts."""
    from limit.solve import iterative_lp, milp
    from scenes import builders as B

    calls = {"milp": 0, "iterative": 0}
    real_milp, real_it = milp.global_minimum, iterative_lp.solve

    def counted_milp(*a, **k):
        calls["milp"] += 1
        return real_milp(*a, **k)

    def counted_it(*a, **k):
        calls["iterative"] += 1
        return real_it(*a, **k)

    monkeypatch.setattr(milp, "global_minimum", counted_milp)
    monkeypatch.setattr(iterative_lp, "solve", counted_it)
    sc = load_scene(B.stack(3, 3, 0.3, 0.5, mu=0.8))
    part = analyse(sc, method="nlp", nlp_options={"global_check": True, "iterative": True}).data["nlp"]
    assert [e["turn_deg"] for e in part["direction_starts"]] == [5, -5]
    assert calls == {"milp": 1, "iterative": 1}
    assert part["global"]["status"] == "optimal"
