"""Step 2 from a dynamic run's collapse state (limit.solve.dem_start, step2.adopt_dem_state, and
``limit solve --dem-start``), against the closed form of two blocks side by side.

The scene (scenes.builders.side_by_side, mu = 0.5): a slender block A (0.2 x 1.0) against a squat
block B (0.5 x 0.6) on a fixed base, under a horizontal body force along +x. Its frictional
collapse (derived in the builder's docstring): A rotates clockwise about its right toe (b1, 0),
pushing B, which slides on the base; alpha = 23/61. The displacement of that mechanism, for a
rotation of A of -1 rad: A's centroid (b1/2, h1/2) turns about the toe, r = (-b1/2, h1/2), so
u_A = omega x r = (h1/2, b1/2) with rz = -1; A's point at B's top corner (b1, h2) moves h2 along
x, and B follows it: u_B = (h2, 0), rz = 0. In 3D (the y axis out of the plane) the same motion
is a rotation of +1 about y: [h1/2, 0, b1/2, 0, 1, 0] and [h2, 0, 0, 0, 0, 0].
"""
import copy
import json

import numpy as np
import pytest

from limit import step2
from limit.analysis import solve_lp
from limit.cli import main
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from limit.solve import dem_start, verify
from limit.solve.outcome import RouteOutcome
from scenes import builders as B
from tests.conftest import side_by_side_collapse_forces

B1, H1, B2, H2 = 0.2, 1.0, 0.5, 0.6
CLOSED = B.side_by_side_alpha(mu=0.5)  # 23/61


def _mechanism(dim, noise=0.0, seed=0):
    if dim == 2:
        d = {"A": [H1 / 2, B1 / 2, -1.0], "B": [H2, 0.0, 0.0]}
    else:
        d = {"A": [H1 / 2, 0.0, B1 / 2, 0.0, 1.0, 0.0], "B": [H2, 0.0, 0.0, 0.0, 0.0, 0.0]}
    rng = np.random.default_rng(seed)
    return {k: (np.asarray(v) + noise * rng.standard_normal(len(v))).tolist() for k, v in d.items()}


def _setup(dim):
    P = assemble(load_scene(B.side_by_side(dim=dim, mu=0.5)))
    sol, _, _ = solve_lp(P)
    assert sol.status == "optimal"
    return P, sol


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("noise", [0.0, 1e-4])
def test_the_collapse_mechanism_as_a_start_gives_the_closed_form(dim, noise):
    """With the rigid mechanism, and with settling noise of 1e-4 of its size on every block dof (a
    DEM's compliance moves every block a little), the piece LP on the flowing faces gives 23/61,
    below the associative LP's 7/17, and the point passes the independent check."""
    P, sol = _setup(dim)
    r = dem_start.solve(P, sol, _mechanism(dim, noise))
    assert r["status"] == "optimal"
    assert r["alpha"] == pytest.approx(CLOSED, rel=1e-9)
    assert sol.alpha == pytest.approx(7 / 17, rel=1e-6) and r["alpha"] < sol.alpha - 1e-3
    assert r["tried"][-1]["verified"] and r["n_flowing"] >= 2


@pytest.mark.parametrize("dim", [2, 3])
def test_a_sliding_block_gives_mu(dim):
    """One block (1.0 wide, 0.5 tall: it rocks only at alpha = b/h = 2) sliding on its base along
    +x: the base joint slides without dilatancy, and alpha = mu = 0.35."""
    P = assemble(load_scene(B.single_block(dim=dim, b=1.0, h=0.5, t=1.0, mu=0.35)))
    sol, _, _ = solve_lp(P)
    free = P.scene.blocks[P.scene.free[0]].id
    r = dem_start.solve(P, sol, {free: [1.0] + [0.0] * (P.scene.ndof - 1)})
    assert r["status"] == "optimal" and r["alpha"] == pytest.approx(0.35, rel=1e-9) and r["misfit"] < 1e-9


def test_the_normal_forces_of_a_dem_state_per_interface():
    """Each interface's normal force is the pair's force along the interface normal, whichever
    block of the pair the record names first."""
    P, _ = _setup(2)
    forces, expected = side_by_side_collapse_forces(P.scene)
    pairs = {(a, b): k for k, (a, b) in enumerate(P.I.pairs(P.scene))}
    got = dem_start.interface_normal_forces(P, forces["pairs"])
    assert [got[pairs[("base", "A")]], got[pairs[("base", "B")]], got[pairs[("A", "B")]]] == pytest.approx(expected)
    flipped = [[b, a] + [-f for f in fs] for a, b, *fs in forces["pairs"]]
    assert dem_start.interface_normal_forces(P, flipped) == pytest.approx(got)
    with pytest.raises(ValueError, match="'C'"):
        dem_start.interface_normal_forces(P, [["A", "C", 1.0, 0.0, 0.0]])


def test_the_contact_forces_alone_start_the_n_iteration_to_the_closed_form():
    """A run's contact forces at the collapse state, with no displacement: the N iteration from
    their normal forces verifies 23/61 (from the displacement alone there is nothing to try)."""
    P, sol = _setup(2)
    forces, _ = side_by_side_collapse_forces(P.scene)
    r = dem_start.solve(P, sol, {}, forces=forces)
    assert r["status"] == "optimal" and r["alpha"] == pytest.approx(CLOSED, rel=1e-6)
    assert r["tau"] is None and r["tried"][0]["how"] == "N iteration from the contact forces"
    assert dem_start.solve(P, sol, {})["status"] == "failed"


def test_a_result_file_gives_the_stiffest_runs_contact_forces():
    soft, stiff = {"alpha": 0.3, "pairs": []}, {"alpha": 0.31, "pairs": []}
    data = {"dem": {"displacement": {"A": [1.0, 0.0, 0.0]},
                    "runs": [{"eps": 1e-5, "held_forces": soft}, {"eps": 2.5e-6, "held_forces": stiff}]}}
    assert dem_start.state_of(data)["forces"] is stiff
    assert dem_start.state_of({"displacement": {"A": [1.0, 0.0, 0.0]}})["forces"] is None


def test_no_motion_gives_no_point():
    P, sol = _setup(2)
    r = dem_start.solve(P, sol, {"A": [0.0, 0.0, 0.0]})
    assert r["status"] == "failed" and r["alpha"] is None and "moves no free block" in r["reason"]


def test_a_displacement_of_the_wrong_dimension_is_named():
    P, sol = _setup(2)
    with pytest.raises(ValueError, match="block 'A': 6 components, a 2D scene has 3"):
        dem_start.solve(P, sol, {"A": [0.0] * 6})


def test_the_dem_state_becomes_step2s_answer_where_step2_finds_nothing(monkeypatch):
    """Step 2's own routes are made to fail: the DEM start's verified point is the answer, route
    "dem-start", and step 2's missing alpha is kept as alpha_step2."""
    P, sol = _setup(2)

    def fail(*a, **k):
        return RouteOutcome(False, reason="stand-in: no verified point")
    monkeypatch.setattr(step2, "run", fail)
    monkeypatch.setattr(step2, "_large", fail)
    res = step2.step2(P, sol, method="nlp", dem_state={"displacement": _mechanism(2), "source": "yade"})
    assert res["status"] == "optimal" and res["route"] == "dem-start" and res["alpha_step2"] is None
    assert res["alpha"] == pytest.approx(CLOSED, rel=1e-9)
    assert res["verification"]["complementarity"] <= verify.TOL_COMP
    assert res["dem_start"]["adopted"] is True and "yade run's collapse state" in res["reason"]


def test_a_dem_state_not_below_step2_is_recorded_and_not_adopted():
    """Step 2 finds 23/61 itself; the DEM state verifies the same alpha, which is not lower."""
    P, sol = _setup(2)
    res = step2.step2(P, sol, method="nlp", dem_state={"displacement": _mechanism(2), "source": "lmgc90"})
    assert res["alpha"] == pytest.approx(CLOSED, rel=1e-4) and res["route"] != "dem-start"
    ds = res["dem_start"]
    assert ds["source"] == "lmgc90" and ds["adopted"] is False
    assert ds["alpha"] == pytest.approx(CLOSED, rel=1e-9) and "not below step 2's" in ds["reason"]


def test_solve_reads_a_dem_result_file(tmp_path, write_scene, capsys):
    scene = write_scene(B.side_by_side(dim=2, mu=0.5))
    dem = tmp_path / "dem.json"
    dem.write_text(json.dumps({"scene": "x", "dem": {"status": "collapsed", "alpha": 0.37,
                                                        "displacement": _mechanism(2)}}))
    out_json = tmp_path / "r.json"
    assert main(["solve", str(scene), "--method", "nlp", "--dem-start", str(dem), "--json", str(out_json)]) == 0
    assert "from the yade collapse state: alpha = 0.377049" in capsys.readouterr().out
    written = json.loads(out_json.read_text())
    assert written["nlp"]["dem_start"]["status"] == "optimal"
    _validate(written)  # the result file's schema knows the part


def test_an_adopted_dem_state_is_a_valid_result_file(monkeypatch):
    from limit.analysis import analyse
    from limit import jsonio

    def fail(*a, **k):
        return RouteOutcome(False, reason="stand-in: no verified point")
    monkeypatch.setattr(step2, "run", fail)
    monkeypatch.setattr(step2, "_large", fail)
    res = analyse(load_scene(B.side_by_side(dim=3, mu=0.5)), method="nlp",
                  nlp_options={"dem_state": {"displacement": _mechanism(3), "source": "yade"}}).data
    assert res["nlp"]["route"] == "dem-start"
    _validate(json.loads(jsonio.dumps(res)))


def _validate(result: dict) -> None:
    from importlib import resources

    import fastjsonschema

    schema = json.loads(resources.files("limit").joinpath("result-1.schema.json").read_text())
    fastjsonschema.compile(schema)(result)


@pytest.mark.parametrize("content,frag", [
    ({"dem": {"status": "stable", "alpha": None}}, "no 'displacement'"),
    ({"dem": {"displacement": {"Z": [0, 0, 0]}}}, "block 'Z' is not in the scene"),
    ([1, 2], "not a result file"),
])
def test_solve_rejects_a_dem_file_without_a_usable_state(tmp_path, write_scene, capsys, content, frag):
    scene = write_scene(B.side_by_side(dim=2, mu=0.5))
    dem = tmp_path / "dem.json"
    dem.write_text(json.dumps(content))
    assert main(["solve", str(scene), "--dem-start", str(dem)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --dem-start") and frag in err


def test_adopting_a_dem_state_makes_a_new_part():
    """adopt_dem_state returns (part, entry) and leaves the part it is given as it was."""
    P, sol = _setup(2)
    part = {"status": "failed", "alpha": None, "reason": "stand-in", "alpha_rejected": 0.5}
    before = copy.deepcopy(part)
    new, entry = step2.adopt_dem_state(P, sol, part, {"displacement": _mechanism(2), "source": "yade"})
    assert part == before
    assert new["dem_start"] is entry and entry["adopted"] is True and new["route"] == "dem-start"
    assert new["alpha"] == pytest.approx(CLOSED, rel=1e-9) and "alpha_rejected" not in new


@pytest.mark.slow  # about 25 s: step 2 in three directions of a 25-block 3D scene
def test_a_nearby_load_directions_collapse_state_can_lower_step_2():
    """The setting direction_starts_deg (limit.analysis._from_turned_directions): Fig. 6's step 2
    from its own starts stops at a local minimum; with the live load turned by 5 degrees step 2
    lands in a lower basin, and that state, tried as a start in the scene's own direction, passes
    the independent check (limit.solve.verify: equilibrium, yield, compatibility and
    complementarity, each within the settings' tolerances) below step 2's own alpha (the setting at
    0: off)."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.scene import load_scene

    sc = load_scene("scenes/catalog/paper-fig6-intersecting-walls-3d.json")
    own = analyse(sc, options=Options(settings={"direction_starts_deg": 0, "friction_starts": False})).data["nlp"]
    assert "direction_starts" not in own
    part = analyse(sc, options=Options(settings={"friction_starts": False})).data["nlp"]  # the default: 5 degrees
    assert part["status"] == "optimal" and part["route"] == "dem-start"
    assert part["alpha"] < own["alpha"] * (1 - 1e-3) and part["alpha_step2"] == pytest.approx(own["alpha"])
    assert [e["turn_deg"] for e in part["direction_starts"]] == [5, -5]
    v = part["verification"]
    assert max(v["equilibrium"], v["yield"], v["compatibility"], v["complementarity"]) < 1e-6


@pytest.mark.slow  # about 20 s: step 2 three times on a 27-block 3D wall
def test_a_reduced_friction_collapse_state_can_lower_step_2():
    """The setting friction_starts (limit.analysis._from_reduced_friction). The out-of-plane wall's
    LP mechanism overturns it about the base edge at t/H = 0.190476 with no joint sliding, and step
    2 from its own starts stays there. With every friction coefficient at 0.25 mu, step 2 finds a
    state in which 4 joints slide (2 of them twisting) at zero normal force while 5 rock; tried as
    a start at the full friction it passes the independent check (limit.solve.verify) at 0.181726,
    4.6 % lower: the MILP's best state quoted in issue 43 (0.1817, 'limit solve --global', 4
    interfaces slide, 2 twist, 5 rock)."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.scene import load_scene

    sc = load_scene("scenes/catalog/wall-out-of-plane-3d.json")
    off = analyse(sc, options=Options(settings={"friction_starts": False}), verdict=False).data["nlp"]
    assert "friction_starts" not in off and off["alpha"] == pytest.approx(sc.expected["alpha_lp"], rel=1e-6)
    part = analyse(sc, verdict=False).data["nlp"]
    assert [e["factor"] for e in part["friction_starts"]] == [0.5, 0.25]
    assert part["status"] == "optimal" and part["route"] == "dem-start" and part["alpha_step2"] == pytest.approx(off["alpha"])
    assert part["alpha"] <= 0.18175 and part["alpha"] < off["alpha"] * 0.96
    v = part["verification"]
    assert max(v["equilibrium"], v["yield"], v["compatibility"], v["complementarity"]) < 1e-6


def _counting_step2(monkeypatch, status, seconds):
    """Replace step 2 by a stub that takes ``seconds`` and returns a part of ``status`` (alpha 0.3
    where it answers); the list it returns records one entry per call."""
    import time as _time

    from limit import step2
    from limit.results.typed import StepResult

    calls = []

    def fake(P, lp_sol, **kw):
        calls.append(kw.get("time_budget", step2.FROM_SETTINGS))
        _time.sleep(seconds)
        return StepResult(status, 0.3 if status == "optimal" else None, seconds, "" if status == "optimal" else "stub")

    monkeypatch.setattr(step2, "step2", fake)
    return calls


def test_without_a_verified_point_the_nearby_starts_share_step_2s_hard_budget(monkeypatch):
    """Step 2 without a verified point stops for good after hard_factor budgets (the settings).
    The nearby starts (turned load, mirror) are part of step 2: once that time is spent none
    begins, and each says why. Before, each ran a whole step 2 of its own, so a scene whose step 2
    fails took three to four times the hard budget (the imported dome: 1,710 s)."""
    from limit.analysis import analyse
    from limit.model.scene import load_scene

    calls = _counting_step2(monkeypatch, "failed", 0.2)
    sc = load_scene("scenes/catalog/wall-3x3-3d.json")
    part = analyse(sc, method="nlp", nlp_options={"time_budget": 0.02}, verdict=False).data["nlp"]  # hard: 0.1 s
    assert len(calls) == 1 and part["status"] == "failed"
    entries = part["direction_starts"] + part["mirror_starts"]
    assert len(entries) == 3 and all("hard budget" in e["reason"] and e["status"] == "failed" for e in entries)


def test_the_nearby_starts_get_what_is_left_of_the_hard_budget(monkeypatch):
    """While time is left of step 2's hard budget, each nearby start begins with its own budget cut
    so that its hard limit ends where step 2's does; once step 2 has a verified point, each has
    the budgets of a step 2 of its own, as the caller gave them."""
    from limit import step2
    from limit.analysis import analyse
    from limit.model.scene import load_scene

    sc = load_scene("scenes/catalog/wall-3x3-3d.json")
    calls = _counting_step2(monkeypatch, "failed", 0.0)
    analyse(sc, method="nlp", nlp_options={"time_budget": 100.0}, verdict=False)
    assert len(calls) == 4 and calls[0] == 100.0
    assert all(0.0 < b < 100.0 for b in calls[1:]) and calls[1] > calls[2] > calls[3]  # the hard limit is 500 s
    assert calls[1] > 99.0  # hardly any time spent before the first one
    calls = _counting_step2(monkeypatch, "optimal", 0.0)
    analyse(sc, method="nlp", nlp_options={"time_budget": 100.0}, verdict=False)
    assert calls == [100.0] * 4
    calls = _counting_step2(monkeypatch, "failed", 0.0)
    analyse(sc, method="nlp", verdict=False)
    assert calls == [step2.FROM_SETTINGS] + [pytest.approx(120.0, rel=0.01)] * 3
