"""Tie design (limit/tie_design.py, ``limit design``): the least tie capacity at which the
frictional alpha reaches a target, by the LP and then step 2's check."""
import json
import subprocess
import sys

import pytest

from limit.analysis import analyse
from limit.model.scene import load_scene
from limit.tie_design import RTOL, design
from scenes import builders as B

RHO_G = 2000.0 * 9.81


def _block_with_post(dim):
    """A 0.4 m wide, 1.0 m tall block (0.3 m deep in 3D) on a fixed base, a fixed post 0.3 m to
    its left, and a candidate tie from the top of the block's left face to the post."""
    d = B.single_block(dim=dim, b=0.4, h=1.0, t=0.3 if dim == 3 else None, mu=0.9)
    if dim == 2:
        d["blocks"].append(B.box_block("post", [-0.4, 0.5], [0.2, 1.0], fixed=True))
        pa, pb = [0.0, 1.0], [-0.3, 1.0]
    else:
        d["blocks"].append(B.box_block("post", [-0.4, 0.15, 0.5], [0.2, 0.3, 1.0], fixed=True))
        pa, pb = [0.0, 0.15, 1.0], [-0.3, 0.15, 1.0]
    tie = {"id": "rod", "from": {"block": "block", "point": pa}, "to": {"block": "post", "point": pb}}
    return d, tie


@pytest.mark.parametrize("dim", [2, 3])
def test_a_single_tie_is_designed_to_the_hand_computed_force(dim):
    """With the tie at the top, overturning needs alpha = b/h + 2 C / W (tests/test_ties.py), so the
    target 0.6 needs C = (0.6 - 0.4) W / 2: 784.8 N in 2D (W = 7,848 N), 235.44 N in 3D (W =
    2,354.4 N). Step 2 keeps the LP's rocking point, so the LP's capacity stands (factor 1)."""
    d, tie = _block_with_post(dim)
    W = RHO_G * 0.4 * 1.0 * (0.3 if dim == 3 else 1.0)
    out = design(d, [tie], 0.6)
    assert out["status"] == "done" and out["factor"] == 1.0
    assert out["ties"][0]["capacity"] == pytest.approx(0.2 * W / 2, rel=1e-6)
    assert out["result"]["nlp"]["alpha"] == pytest.approx(0.6, rel=1e-6)


def test_the_settings_reach_every_trials_analysis(monkeypatch, capsys):
    """``design(settings=...)`` (``limit design --set``): each trial's analysis gets the changed
    setting, and the answer is the hand-computed one of the test above; a bad --set is rejected
    input (exit 2) naming the key."""
    import limit.analysis as an
    from limit.cli import main

    seen = []
    real = an.analyse

    def spy(scene, *a, options=None, **kw):
        seen.append(options.settings.friction_starts if options is not None else None)
        return real(scene, *a, options=options, **kw)

    monkeypatch.setattr(an, "analyse", spy)
    d, tie = _block_with_post(2)
    out = design(d, [tie], 0.6, settings={"friction_starts": False})
    assert out["status"] == "done" and out["ties"][0]["capacity"] == pytest.approx(0.2 * RHO_G * 0.4 / 2, rel=1e-6)
    assert seen and all(v is False for v in seen)
    capsys.readouterr()
    assert main(["design", "scenes/catalog/block-tied-2d.json", "--target-alpha", "0.7", "--set", "frob=1"]) == 2
    assert "unknown setting 'frob'" in capsys.readouterr().err


@pytest.mark.slow  # about 25 s: a tie design with step 2 at every trial force
def test_step_2_raises_the_lps_capacity_to_reach_the_target():
    """The side-by-side blocks (frictional 23/61 below the LP's 7/17 untied) with two candidate
    ties from the slender block to a post: the LP picks the least total capacity at which its alpha
    is 0.45 (less of it falls short), step 2 then finds 0.43 there, and the common factor grows
    until step 2 reaches 0.45, the last factor below within RTOL of it."""
    d = B.side_by_side(dim=2)
    d["blocks"].append(B.box_block("post", [-0.4, 0.5], [0.2, 1.0], fixed=True))
    cands = [{"id": "top", "from": {"block": "A", "point": [0.0, 1.0]}, "to": {"block": "post", "point": [-0.3, 1.0]}},
             {"id": "low", "from": {"block": "A", "point": [0.0, 0.3]}, "to": {"block": "post", "point": [-0.3, 0.3]}}]
    out = design(d, cands, 0.45)
    assert out["status"] == "done"
    lp_caps = out["lp_capacities"]
    for k, scale in ((1.0, 1.0), (1.0, 1.0 - 1e-3)):
        ties = [dict(c, capacity=v * scale) for c, v in zip(cands, lp_caps) if v > 0]
        a = analyse(load_scene(dict(d, ties=ties)), method="lp").data["lp"]["alpha"]
        assert (a == pytest.approx(0.45, rel=1e-6)) if scale == 1.0 else a < 0.45
    assert out["factor"] > 1.0
    nlp = out["result"]["nlp"]
    assert nlp["status"] == "optimal" and nlp["alpha"] >= 0.45 * (1 - 1e-9)
    below = max(f for f, a in out["trials"] if a is not None and a < 0.45)
    assert out["factor"] - below <= 2 * RTOL * out["factor"]


@pytest.mark.slow  # about 18 s: limit design end to end in a subprocess
def test_limit_design_writes_the_designed_scene(tmp_path):
    """End to end: the designed scene solves to the target; a bound below the need is 'infeasible'
    (exit 1, said); a target the untied block reaches needs no tie."""
    d, tie = _block_with_post(2)
    d["ties"] = [dict(tie, capacity=5000.0)]  # the scene's own tie: a candidate, its capacity a bound
    p, out = tmp_path / "block.json", tmp_path / "designed.json"
    p.write_text(json.dumps(d))
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.6", "-o", str(out)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "rod 784.8 N" in r.stdout
    assert analyse(load_scene(json.loads(out.read_text())), method="lp").data["lp"]["alpha"] == pytest.approx(0.6, rel=1e-6)
    d["ties"][0]["capacity"] = 500.0
    p.write_text(json.dumps(d))
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.6"],
                       capture_output=True, text=True)
    assert r.returncode == 1 and "design infeasible" in r.stdout
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.3"],
                       capture_output=True, text=True)
    assert r.returncode == 0 and "none needed" in r.stdout


@pytest.mark.yade
def test_yade_carries_the_designed_target_and_not_without_the_tie():
    """The single tie designed for alpha = 0.6 (784.8 N, above): YADE's pushover of the tied block
    collapses within 2 % of 0.6, the block without it within 2 % of its own 0.4."""
    from dem_validation.api import run_scene

    d, tie = _block_with_post(2)
    out = design(d, [tie], 0.6)
    tied = run_scene(load_scene(dict(d, ties=out["ties"])))
    assert tied["status"] == "collapsed" and tied["alpha"] == pytest.approx(0.6, rel=0.02)
    bare = run_scene(load_scene(d))
    assert bare["status"] == "collapsed" and bare["alpha"] == pytest.approx(0.4, rel=0.02)


def _facade_with_cross_wall(demand=None):
    """An out-of-plane facade with a cross wall (3D, mu 0.6, density 2000 kg/m^3): the facade
    'facade' (tag front) 2.0 m long (x), 0.25 m thick (y in [0, 0.25]) and 1.5 m tall, W_F =
    RHO_G x 0.75 = 14,715 N; the cross wall 'cross' (tag cross) 0.2 m thick, 2.0 m long behind it
    (y in [0.25, 2.25]), 1.5 m tall, W_C = 11,772 N, abutting the facade's back face; both on a
    fixed base. The live load pushes every block along -y: the facade rocks away from the cross
    wall about its outer toe at t/H = 0.25 / 1.5 = 1/6."""
    blocks = [B.base(3, -0.5, 2.5, -0.5, 2.5),
              B.box_block("facade", [1.0, 0.125, 0.75], [2.0, 0.25, 1.5], tags=["front"]),
              B.box_block("cross", [1.0, 1.25, 0.75], [0.2, 2.0, 1.5], tags=["cross"])]
    d = B.scene("facade-cross-wall-3d", 3, blocks, friction=0.6,
                live=[{"type": "body_force", "direction": [0.0, -1.0, 0.0]}])
    if demand:
        d["demand"] = demand
    return d


def _hand_tie(alpha, z=1.25):
    """The tie force at height z (m) that holds the facade's rocking at alpha. Virtual rotation
    theta about the outer toe: the load does alpha W_F (H/2) theta, its weight takes W_F (t/2)
    theta, the tie T z theta: T = W_F (alpha H/2 - t/2) / z. The cross wall stays: it would have to
    slide (mu W_C = 7,063 N against T + alpha W_C <= 4,709 N at alpha 0.3) or rock in its plane
    (W_C x 1.0 m against alpha W_C 0.75 m + 1.25 T) first."""
    return RHO_G * 0.75 * (alpha * 0.75 - 0.125) / z


def test_wall_to_wall_candidates_pair_the_tagged_blocks_at_each_level():
    """One block per group, two levels: two candidates, each through the blocks' centroids'
    verticals at its level; a tag that no block has, and a level that cuts neither, are named."""
    from limit.errors import SceneError
    from limit.tie_candidates import wall_to_wall

    c = wall_to_wall(_facade_with_cross_wall(), "front", "cross", levels=[0.75, 1.25])
    assert [(t["from"]["block"], t["to"]["block"]) for t in c] == [("facade", "cross")] * 2
    assert [t["from"]["point"] for t in c] == [[1.0, 0.125, 0.75], [1.0, 0.125, 1.25]]
    assert [t["to"]["point"] for t in c] == [[1.0, 1.25, 0.75], [1.0, 1.25, 1.25]]
    assert wall_to_wall(_facade_with_cross_wall(), "front", "cross")[0]["from"]["point"][2] == 0.75  # default
    with pytest.raises(SceneError, match="tag 'back'"):
        wall_to_wall(_facade_with_cross_wall(), "front", "back")
    with pytest.raises(SceneError, match="level 2 cuts no block tagged 'front'"):
        wall_to_wall(_facade_with_cross_wall(), "front", "cross", levels=[2.0])


@pytest.mark.slow  # about 35 s: a tie design (bisection on the tie force) on a facade and its cross wall
def test_facade_tied_to_its_cross_wall_gets_the_hand_computed_tie():
    """Target 0.3 over candidates at 0.75 and 1.25 m: the higher one, with T = W_F (0.3 x 0.75 -
    0.125) / 1.25 = 1,177.2 N (:func:`_hand_tie`). The associative LP asks for a quarter of that
    (its rocking would open the facade's joint with the cross wall as it slides, by dilatancy);
    step 2 raises it by the common factor to the hand value, within RTOL."""
    from limit.tie_candidates import wall_to_wall

    d = _facade_with_cross_wall()
    out = design(d, wall_to_wall(d, "front", "cross", levels=[0.75, 1.25]), 0.3)
    assert out["status"] == "done"
    assert [t["id"] for t in out["ties"]] == ["w2w-1-facade-cross"]
    assert out["ties"][0]["capacity"] == pytest.approx(_hand_tie(0.3), rel=RTOL)
    assert _hand_tie(0.3) == pytest.approx(1177.2, rel=1e-9)
    assert out["result"]["nlp"]["alpha"] >= 0.3 * (1 - 1e-9)


@pytest.mark.slow  # about 45 s: a tie design (bisection on the tie force) for the demand
def test_design_for_the_demand_passes_the_linear_check_at_the_hand_computed_tie():
    """The scene's demand as the target (no --target-alpha): ag 0.3 g, S 1.2, q 2 at ground level,
    so the linear check needs a0* >= ag S / q = 0.18 g (C8A.4.7). The facade's rocking has e* = 1
    (one block: M* = (P dx)^2 / (g P dx^2) = P / g), so a0* = alpha0 g / FC and the check passes
    from alpha0 = 0.18 FC = 0.243 (FC 1.35): T = W_F (0.243 x 0.75 - 0.125) / 1.25 = 673.947 N.
    Untied (alpha0 1/6) the check fails, ratio (1/6) / 0.243 = 0.6859."""
    from limit.tie_candidates import wall_to_wall
    from limit.tie_design import design_for_demand

    dem = {"ag_g": 0.3, "S": 1.2, "F0": 2.5, "TB": 0.15, "TC": 0.5, "TD": 2.8, "q": 2.0, "fc": 1.35}
    d = _facade_with_cross_wall(dem)
    out = design_for_demand(d, wall_to_wall(d, "front", "cross", levels=[0.75, 1.25]))
    assert out["status"] == "done"
    assert out["rounds"][0][2] == pytest.approx((1 / 6) / 0.243, rel=1e-9)
    assert out["ties"][0]["capacity"] == pytest.approx(_hand_tie(0.243), rel=2 * RTOL)
    assert out["check"]["linear"]["pass"] and out["check"]["linear"]["ratio"] == pytest.approx(1.0, abs=2e-3)


@pytest.mark.slow  # about 40 s: limit design end to end, candidates generated and designed
def test_limit_design_generates_wall_to_wall_candidates(tmp_path):
    """End to end on the command line: the generated candidates, the designed tie, the written
    scene; --levels without --wall-to-wall is rejected (exit 2)."""
    p, out = tmp_path / "facade.json", tmp_path / "tied.json"
    p.write_text(json.dumps(_facade_with_cross_wall()))
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.3", "--wall-to-wall",
                        "front", "cross", "--levels", "0.75", "1.25", "-o", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "2 candidate ties, wall to wall" in r.stderr
    tied = json.loads(out.read_text())["ties"]
    assert len(tied) == 1 and tied[0]["capacity"] == pytest.approx(1177.2, rel=RTOL)
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.3", "--levels", "1"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "--levels" in r.stderr


@pytest.mark.yade
def test_yade_carries_the_target_with_the_designed_facade_tie_and_not_without(tmp_path):
    """The facade and cross wall above, its tie designed for 0.3 (1,177.2 N by hand) by ``limit
    design ... --dem``: YADE's pushover of the tied scene collapses within 2 % of 0.3 (printed and
    in the record); the untied one at the facade's rocking, 1/6, within 2 % (far below the target)."""
    from dem_validation.api import run_scene

    d = _facade_with_cross_wall()
    p, rec = tmp_path / "facade.json", tmp_path / "design.json"
    p.write_text(json.dumps(d))
    r = subprocess.run([sys.executable, "-m", "limit", "design", str(p), "--target-alpha", "0.3", "--wall-to-wall",
                        "front", "cross", "--levels", "0.75", "1.25", "--dem", "--json", str(rec)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    dem = json.loads(rec.read_text())["dem"]
    assert dem["status"] == "collapsed" and dem["alpha"] == pytest.approx(0.3, rel=0.02)
    assert "YADE: collapsed, collapses at alpha = " in r.stdout
    bare = run_scene(load_scene(d))
    assert bare["status"] == "collapsed" and bare["alpha"] == pytest.approx(1 / 6, rel=0.02)
