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
        a = analyse(load_scene(dict(d, ties=ties)), method="lp")["lp"]["alpha"]
        assert (a == pytest.approx(0.45, rel=1e-6)) if scale == 1.0 else a < 0.45
    assert out["factor"] > 1.0
    nlp = out["result"]["nlp"]
    assert nlp["status"] == "optimal" and nlp["alpha"] >= 0.45 * (1 - 1e-9)
    below = max(f for f, a in out["trials"] if a is not None and a < 0.45)
    assert out["factor"] - below <= 2 * RTOL * out["factor"]


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
    assert analyse(load_scene(json.loads(out.read_text())), method="lp")["lp"]["alpha"] == pytest.approx(0.6, rel=1e-6)
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
