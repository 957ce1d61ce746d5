"""The limit-analysis bracket as the self-check of a dynamic result (dem_validation/bracket.py),
in the DEM command's result file and in the validation report's tables."""
import json
import math

import pandas as pd
import pytest

import dem_validation.cli
from dem_validation.bracket import judge, judge_with_start, label, limit_analysis
from limit.model.scene import load_scene
from reports import table
from scenes import builders as B
from tests.conftest import eccentric_slab_run, side_by_side_collapse_forces

CLOSED = B.side_by_side_alpha(mu=0.5)  # 23/61

LA = {"fric_alpha": 0.3, "lp_alpha": 0.4}


@pytest.mark.parametrize("alpha,verdict,side", [
    (0.2955, "suspect", "low"),  # 1.5 % below step 2's 0.3: beyond the 1 % slack
    (0.2975, "inside", None),    # within the 1 % slack below step 2
    (0.35, "inside", None),
    (0.4035, "inside", None),    # within the 1 % slack above the LP
    (0.2, "suspect", "low"),
    (0.41, "suspect", "high"),
])
def test_judge_places_a_collapse_in_the_bracket(alpha, verdict, side):
    b = judge({"status": "collapsed", "alpha": alpha}, LA)
    assert (b["verdict"], b["side"]) == (verdict, side)
    assert label(b) == ("" if verdict == "inside" else f"suspect {side}")
    if side == "low":
        assert "below step 2's frictional collapse at 0.3" in b["reason"] and "--dem-start" in b["reason"]
    if side == "high":
        assert "above the associative LP's upper bound 0.4" in b["reason"]
    moving = judge({"status": "collapsed", "alpha": alpha, "dt_converged": False}, LA)
    assert ("still moved at its last halving" in moving["reason"]) == (side == "low")
    runs = [{"dt": 1e-3, "alpha": 0.8 * alpha}, {"dt": 5e-4, "alpha": 0.9 * alpha}, {"dt": 2.5e-4, "alpha": alpha}]
    rising = judge({"status": "collapsed", "alpha": alpha, "dt_converged": True, "runs": runs}, LA)
    assert ("rose at every halving" in rising["reason"]) == (side == "low")
    flat = judge({"status": "collapsed", "alpha": alpha, "dt_converged": True, "runs": runs[::-1]}, LA)
    assert "halving" not in flat["reason"]


def test_in_3d_the_lp_bound_is_widened_to_the_circular_cone():
    """A block sliding at mu = 0.4: the 24 inscribed faces give 0.4 cos(pi/24) = 0.39658 as the LP
    in the middle of a face; an engine on the circular cone collapses at 0.4 (+0.25 %: 0.401), which
    is 1.1 % above 0.39658 but inside once the bound is 0.39658 / cos(pi/24) = 0.4."""
    from dem_validation.bracket import cone_lp_factor

    la = {"fric_alpha": 0.39658, "lp_alpha": 0.39658}
    assert judge({"status": "collapsed", "alpha": 0.401}, la)["side"] == "high"
    assert judge({"status": "collapsed", "alpha": 0.401}, {**la, "lp_factor": cone_lp_factor(3)})["verdict"] == "inside"
    assert cone_lp_factor(2) == 1.0 and cone_lp_factor(3) == pytest.approx(1 / math.cos(math.pi / 24))


def test_judge_without_a_collapse_or_without_step2():
    assert judge({"status": "stable", "alpha": None}, LA)["verdict"] == "unchecked"
    b = judge({"status": "collapsed", "alpha": 0.1}, {"fric_alpha": None, "lp_alpha": 0.4})
    assert b["verdict"] == "inside" and "lower side is not checked" in b["reason"]
    assert judge({"status": "collapsed", "alpha": 0.5}, {"fric_alpha": None, "lp_alpha": 0.4})["side"] == "high"


def test_limit_analysis_of_the_bracket_uses_the_cone_in_3d():
    """A squat block (1 x 1 x 0.5, mu 0.4) loaded at 45 degrees in plan slides at mu = 0.4 on the
    Coulomb cone; the paper's 4 circumscribed faces give 0.4 sqrt(2) = 0.566 there, the 24
    inscribed ones 0.4 cos(pi/24) = 0.3966 at worst (in the middle of a face) and 0.4 at a corner."""
    d = B.single_block(dim=3, b=1.0, h=0.5, t=1.0, mu=0.4)
    d["interfaces"] = {"sliding_faces": 4}
    c = 0.5 ** 0.5
    d["loads"]["live"] = [{"type": "body_force", "direction": [c, c, 0]}]  # unit length: a body force is not normalised
    la = limit_analysis(load_scene(d))
    assert 0.4 * math.cos(math.pi / 24) - 1e-6 <= la["lp_alpha"] <= 0.4 + 1e-9
    assert la["model"].startswith("24 inscribed")


def test_the_dem_command_writes_the_bracket(tmp_path, write_scene, monkeypatch, capsys):
    """The engine is replaced by a stand-in that collapses at 0.2 on a block that rocks at
    b / h = 0.4 (step 2 skipped: rocking): suspect low, in the file and on the screen."""
    from dem_validation import engines

    def fake(scene, p, **kw):
        return engines.DemResult.from_dict(
            {"status": "collapsed", "alpha": 0.2, "alpha_uncertainty": 0.001, "runs": [], "time_s": 1.0,
             "displacement": {}, "extrapolation": {"method": "richardson"}})
    monkeypatch.setattr(engines.get("yade"), "run", fake)
    scene = write_scene(B.single_block(dim=2, b=0.4, h=1.0, t=1.0, mu=0.8))
    out = tmp_path / "dem.json"
    assert dem_validation.cli.main(["run", str(scene), "--json", str(out), "--quiet"]) == 0
    dem = json.loads(out.read_text())["dem"]
    assert dem["suspect"] is True and dem["bracket"]["side"] == "low"
    assert dem["bracket"]["fric_alpha"] == pytest.approx(0.4, rel=1e-6)
    assert "SUSPECT (low): 0.2 is 50.0 % below" in capsys.readouterr().out
    assert dem_validation.cli.main(["run", str(scene), "--json", str(out), "--quiet", "--no-bracket"]) == 0
    assert "bracket" not in json.loads(out.read_text())["dem"]


def _side_by_side_run(alpha):
    """A stand-in DEM result on the side-by-side blocks (mu 0.5): collapsed at ``alpha``, with the
    contact forces of the closed-form collapse state (tests/conftest.py) and no motion."""
    scene = load_scene(B.side_by_side(dim=2, mu=0.5))
    forces, _ = side_by_side_collapse_forces(scene)
    return scene, {"status": "collapsed", "alpha": alpha, "displacement": {"A": [0.0, 0.0, 0.0]},
                   "runs": [{"eps": 2.5e-6, "held_forces": forces}]}


def test_a_run_below_the_minimum_is_told_that_no_rigid_state_lies_near_it():
    """A run at 0.30 against step 2's 23/61 (closed form): suspect low, and step 2 from the
    run's contact forces verifies 23/61 again, which the reason says."""
    scene, dem = _side_by_side_run(0.30)
    b = judge_with_start(scene, dem, {"fric_alpha": CLOSED, "lp_alpha": 7 / 17})
    assert b["verdict"] == "suspect" and b["side"] == "low"
    assert b["dem_start"]["alpha"] == pytest.approx(CLOSED, rel=1e-6) and b["dem_start"]["adopted"] is False
    assert "no lower rigid-block state near this run's" in b["reason"]


def test_a_run_below_a_step2_that_stopped_high_is_judged_against_the_lower_state():
    """Step 2 given as 0.41 (as if it had stopped above the minimum) and a run at 0.375: from the
    run's forces step 2 verifies 23/61 = 0.37705, and against that the run is inside the 1 % slack."""
    scene, dem = _side_by_side_run(0.375)
    assert judge(dem, {"fric_alpha": 0.41, "lp_alpha": 0.42})["verdict"] == "suspect"
    b = judge_with_start(scene, dem, {"fric_alpha": 0.41, "lp_alpha": 0.42})
    assert b["verdict"] == "inside" and b["fric_alpha"] == pytest.approx(CLOSED, rel=1e-6)
    assert b["fric_alpha_step2"] == 0.41 and b["dem_start"]["adopted"] is True


def test_a_3d_run_below_the_papers_joints_is_judged_on_the_engines_point_contacts():
    """A slab pushed 0.25 m off its centre (mu 0.6). On the paper's joints sliding and twisting
    are independent, so it slides at mu along x, which the 24 inscribed faces meet at mid-face:
    mu cos(pi/24) = 0.59487. On point contacts at its four corners, as the engines carry it, a
    collapse state with equal normal forces lies at the closed form of
    :func:`scenes.builders.eccentric_slab_alpha` (0.54417; the inscribed faces and other normal
    forces can only lower the minimum). A run at
    0.54 with the base's force (-alpha W, 0, W) on the slab is suspect low on the paper's joints
    and inside once judged on point contacts."""
    e, mu = 0.25, 0.6
    scene = load_scene(B.eccentric_slab(e=e, mu=mu))
    paper = limit_analysis(scene)
    assert paper["fric_alpha"] == pytest.approx(mu * math.cos(math.pi / 24), rel=1e-5)
    corners = B.eccentric_slab_alpha(e, mu=mu)
    assert corners < 0.99 * paper["fric_alpha"]
    dem = eccentric_slab_run(scene, 0.54)
    assert judge(dem, paper)["side"] == "low"
    b = judge_with_start(scene, dem, paper)
    assert b["verdict"] == "inside", b["reason"]
    pc = b["point_contacts"]
    assert pc["alpha"] <= corners * (1 + 1e-6) and pc["alpha"] <= pc["lp_alpha"] * (1 + 1e-6)
    assert b["fric_alpha"] == pc["alpha"] and b["model"].startswith("point contacts")
    assert b["fric_alpha_step2"] == pytest.approx(paper["fric_alpha"])


def test_a_centred_push_gives_the_same_on_point_contacts():
    """Pushed through its centre the slab slides at mu on either joint model (the corners' closed
    form tends to mu as e -> 0): a run at 0.5 stays suspect low, and the reason says that point
    contacts verified nothing lower."""
    scene = load_scene(B.eccentric_slab(e=0.0, mu=0.6))
    assert B.eccentric_slab_alpha(1e-6, mu=0.6) == pytest.approx(0.6, rel=1e-5)
    paper = limit_analysis(scene)
    dem = eccentric_slab_run(scene, 0.5, rz=0.0)
    b = judge_with_start(scene, dem, paper)
    assert b["verdict"] == "suspect" and b["side"] == "low"
    assert b["point_contacts"]["alpha"] >= paper["fric_alpha"] * (1 - 1e-6)
    assert "on point contacts" in b["reason"] and "not lower" in b["reason"]


def test_the_engines_table_flags_a_suspect_result():
    rows = [{"name": "w", "dim": 2, "n_free": 3, "lp_alpha": 0.30, "fric_alpha": 0.2755, "cone_alpha": None,
             "cone_status": "skipped", "dem_alpha": 0.182, "dem_status": "collapsed", "dem_vs_la": -0.34,
             "dem_bracket": "suspect low", "lmgc_alpha": 0.29, "lmgc_status": "collapsed", "lmgc_bracket": "",
             "lmgc_vs_la": 0.05, "dstart_from": ""}]
    text = table.engines_markdown(pd.DataFrame(rows))
    assert "| 0.182 (suspect low) |" in text and "| 0.29 |" in text
    assert "1 of 2 collapsed engine results" in text
