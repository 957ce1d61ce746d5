"""Bonded joints: cohesion c and tensile strength ft (Pa) of the scene's ``joints`` groups in the
yield domain (limit/model/yield_domain.py), in both steps and both interface models, against
closed forms derived here. Blocks: density 2000 kg/m^3, g = 9.81 m/s^2, a 2D scene 1 m thick;
the live load is a horizontal body force (alpha times the weight, at the centroid)."""
import json
import math

import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.model.assemble import Options
from limit.model.scene import load_scene
from scenes import builders as B

RHO_G = 2000.0 * 9.81


def _glued(dim, model="paper", **joint):
    """A 1.0 m wide, 0.5 m tall block (0.4 m deep in 3D) on a fixed base, mu 0.3."""
    d = B.single_block(dim=dim, b=1.0, h=0.5, t=0.4 if dim == 3 else None, mu=0.3)
    d["joints"] = [{"between": {"blocks": ["base", "block"]}, **joint}]
    return d


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # about 1.5-2.5 s each
@pytest.mark.parametrize("model", ["paper", "vertex"])
def test_a_glued_block_slides_at_mu_plus_cA_over_W(dim, model):
    """Sliding on a joint with cohesion: alpha W = mu W + c A, alpha = mu + c A / W. 2D: W =
    RHO_G 1.0 x 0.5 x 1 = 9,810 N, A = 1.0 x 1 m^2; 3D: W = 3,924 N, A = 0.4 m^2; c = 2,000 Pa
    gives c A / W = 0.2039 both ways, alpha = 0.503874. Overturning needs b / h = 2 (and more
    with cohesion), so sliding governs. The associative LP's dilatant slide dissipates c A per
    unit slip and lifts W by mu per unit slip: the same alpha."""
    res = analyse(load_scene(_glued(dim, cohesion=2000.0)), method="nlp",
                  options=Options(model=model)).data
    W = RHO_G * 1.0 * 0.5 * (0.4 if dim == 3 else 1.0)
    A = 0.4 if dim == 3 else 1.0
    want = 0.3 + 2000.0 * A / W
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["status"] == "optimal"


def _tall(dim, **joint):
    """A 0.4 m wide, 1.0 m tall block (0.3 m deep in 3D) on a fixed base, mu 0.8."""
    d = B.single_block(dim=dim, b=0.4, h=1.0, t=0.3 if dim == 3 else None, mu=0.8)
    d["joints"] = [{"between": {"blocks": ["base", "block"]}, **joint}]
    return d


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # 3D: about 3 s
def test_tensile_strength_raises_overturning_to_b_over_h_times_1_plus_ftA_over_W(dim):
    """Overturning about the toe with uniform tension ft over the base: moments about the toe,
    alpha W h/2 = W b/2 + ft A b/2, so alpha = (b/h)(1 + ft A / W). 2D: W = 7,848 N, A = 0.4 m^2;
    3D: W = 2,354.4 N, A = 0.12 m^2; ft = 5,000 Pa: alpha = 0.4 x 1.254842 = 0.501937 both ways.
    Sliding needs mu = 0.8 (more with cohesion). The paper's model carries ft without cohesion
    (the joint is in compression overall); the vertex model's corners only with c >= mu ft
    (their Coulomb cones' apex), and without cohesion fall back to the dry b / h = 0.4."""
    W = RHO_G * 0.4 * 1.0 * (0.3 if dim == 3 else 1.0)
    A = 0.4 * (0.3 if dim == 3 else 1.0)
    want = 0.4 * (1.0 + 5000.0 * A / W)
    res = analyse(load_scene(_tall(dim, tensile_strength=5000.0)), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)
    both = _tall(dim, tensile_strength=5000.0, cohesion=10000.0)
    res = analyse(load_scene(both), method="nlp", options=Options(model="vertex")).data
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)
    res = analyse(load_scene(_tall(dim, tensile_strength=5000.0)), method="nlp", options=Options(model="vertex")).data
    assert res["lp"]["alpha"] == pytest.approx(0.4, rel=1e-6)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_cohesive_stack_slides_on_its_lowest_joint(dim):
    """Three 1.0 x 0.3 m blocks (1.0 m deep in 3D, 1 m thick in 2D), mu 0.6, c = 3,000 Pa on every
    joint (A = 1 m^2). The joint under block k carries W_k = (3 - k) W, W = 5,886 N, and slides at
    mu + c A / W_k: 0.7699, 0.8548, 1.1097 for k = 0, 1, 2; the blocks above joint k overturn at
    b / ((3 - k) h) >= 1.11 (more with cohesion). The least is the lowest joint: alpha = 0.6 +
    3000 / 17658."""
    d = B.stack(3, dim=dim, b=1.0, h=0.3, mu=0.6)
    d["joints"] = [{"between": {"tags": [t, u]}, "cohesion": 3000.0}
                   for t, u in (("course-0", "course-1"), ("course-1", "course-2"))]
    d["joints"].append({"between": {"blocks": ["base", "s0"]}, "cohesion": 3000.0})
    res = analyse(load_scene(d), method="nlp").data
    want = 0.6 + 3000.0 / (3 * RHO_G * 0.3)
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)


def _hanging(**joint):
    """A 0.3 x 0.3 m block glued to the face of a fixed wall, nothing under it; the live load
    pulls it away from the wall (+x)."""
    wall = B.box_block("wall", [-0.25, 0.15], [0.5, 0.3], fixed=True)
    blk = B.box_block("corbel", [0.15, 0.15], [0.3, 0.3])
    d = B.scene("corbel-2d", 2, [wall, blk], friction=0.6)
    if joint:
        d["joints"] = [{"between": {"blocks": ["wall", "corbel"]}, **joint}]
    return d


def test_a_block_held_by_mortar_alone():
    """The corbel (W = RHO_G 0.09 = 1,765.8 N) hangs on a vertical joint 0.3 m long (A = 0.3 m^2,
    half length l = 0.15 m). Pulled off by alpha W: N = -alpha W, V = W, and about the joint's
    centre the weight's moment W 0.15. Rocking: W 0.15 <= l (N + ft A), alpha <= (ft A - W) / W;
    sliding: W <= mu N + c A, alpha <= (c A - W) / (mu W). ft = 20 kPa, c = 15 kPa: 2.39789
    against 2.58066, so alpha = (6000 - 1765.8) / 1765.8. Dry, the dead load alone collapses
    it: the LP is infeasible and names the block."""
    W = RHO_G * 0.09
    res = analyse(load_scene(_hanging(tensile_strength=20000.0, cohesion=15000.0)), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx((6000.0 - W) / W, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx((6000.0 - W) / W, rel=1e-6)
    dry = analyse(load_scene(_hanging()), method="nlp").data
    assert dry["lp"]["status"] == "infeasible"
    assert "corbel" in json.dumps(dry["lp"])


@pytest.mark.parametrize("key, value", [("cohesion", -1.0), ("tensile_strength", "strong"),
                                        ("cohesion", math.inf)])
def test_a_bad_stress_is_named(key, value):
    d = _glued(2)
    d["joints"][0][key] = value
    with pytest.raises(SceneError, match=rf"joints\[0\]\.{key}: "):
        load_scene(d)


def test_the_dry_dem_models_skip_a_bonded_scene_with_the_reason():
    """LMGC90's and YADE's polyhedra contact laws are dry: a scene with cohesion is skipped there,
    never run as if dry (YADE's vertex model bonds the joints: test_yade_bonded_joints_...)."""
    from dem_validation.api import run_loaded
    from dem_validation.lmgc import run_loaded_lmgc90

    s = load_scene(_glued(2, cohesion=2000.0))
    for out in (run_loaded(s, {}, contact="polyhedra"), run_loaded_lmgc90(s, {})):
        assert out["status"] == "skipped"
        assert "cohesion or tensile strength" in out["reason"]


def test_the_independent_routes_carry_the_cohesion():
    """The MILP's global minimum and the iterative LP (Gilbert, Casapulla & Ahmed) of the cohesive
    stack above reach its closed form too: 0.6 + 3000 / 17658."""
    d = B.stack(3, dim=2, b=1.0, h=0.3, mu=0.6)
    d["joints"] = [{"between": {"tags": ["course-0", "course-1"]}, "cohesion": 3000.0},
                   {"between": {"tags": ["course-1", "course-2"]}, "cohesion": 3000.0},
                   {"between": {"blocks": ["base", "s0"]}, "cohesion": 3000.0}]
    res = analyse(load_scene(d), method="nlp", nlp_options={"global_check": True, "iterative": True}).data
    want = 0.6 + 3000.0 / (3 * RHO_G * 0.3)
    assert res["nlp"]["global"]["status"] == "optimal"
    assert res["nlp"]["global"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["iterative_lp"]["alpha"] == pytest.approx(want, rel=1e-6)


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # about 2 s each
@pytest.mark.parametrize("model", ["paper", pytest.param("vertex", marks=pytest.mark.slow)])
def test_radenkovic_bound_of_a_glued_block_is_its_friction_free_slide(dim, model):
    """The lower bound (paper, section 3; limit/solve/radenkovic.py): the associative collapse of
    the joint with friction removed and the least sliding strength c' A, c' = c - mu ft' with
    ft' = min(ft, c / mu). The block of test_a_glued_block_slides_at_mu_plus_cA_over_W (2D: W =
    9,810 N, A = 1 m^2; 3D: W = 3,924 N, A = 0.4 m^2), mu 0.3:
    * c = 2,000 Pa, ft = 0: c' A / W = 0.203874 (both dims), below step 2's 0.503874;
    * c = 2,000 Pa, ft = 1,000 Pa: c' = 1,700 Pa, alpha = 0.173293.
    Overturning without friction is the same (b/h)(1 + ft' A / W) >= 2, so sliding governs."""
    W = RHO_G * 1.0 * 0.5 * (0.4 if dim == 3 else 1.0)
    A = 0.4 if dim == 3 else 1.0
    for ft, c_eff in ((0.0, 2000.0), (1000.0, 1700.0)):
        res = analyse(load_scene(_glued(dim, cohesion=2000.0, tensile_strength=ft)), method="nlp",
                      options=Options(model=model)).data
        lb = res["lower_bound"]
        assert lb["method"] == "radenkovic" and lb["status"] == "optimal"
        assert lb["alpha"] == pytest.approx(c_eff * A / W, rel=1e-6)
        assert lb["alpha"] < res["nlp"]["alpha"]


def test_radenkovic_bound_is_absent_on_dry_joints_and_uninformative_when_friction_carries_the_dead_load():
    """Dry joints: no bound is computed (it would be 0). A 1 x 0.5 m block on a base inclined so
    that friction alone holds it under its weight: with a small cohesion the friction-free body
    cannot carry the dead load, and the bound says so (status infeasible, alpha None).
    Inclination: gravity tilted by 10 deg (tan 10 = 0.176 < mu 0.3); c A = 100 N against the
    dead-load shear W sin 10 = 1,703 N."""
    res = analyse(load_scene(_glued(2)), method="lp").data
    assert "lower_bound" not in res
    tied = _glued(2)  # a tie's capacity is no cohesion: still no bound
    tied["ties"] = [{"id": "rod", "from": {"block": "block", "point": [0.5, 0.25]},
                     "to": {"block": "base", "point": [0.5, -0.1]}, "capacity": 100.0}]
    assert "lower_bound" not in analyse(load_scene(tied), method="lp").data
    d = _glued(2, cohesion=100.0)
    g = 9.81
    d["gravity"] = [g * math.sin(math.radians(10)), -g * math.cos(math.radians(10))]
    res = analyse(load_scene(d), method="lp").data
    assert res["lp"]["status"] == "optimal"
    assert res["lower_bound"]["status"] == "infeasible" and res["lower_bound"]["alpha"] is None
    assert "dead load" in res["lower_bound"]["reason"]


@pytest.mark.yade
@pytest.mark.parametrize("dim", [2, 3])
def test_yade_bonded_joints_reach_the_closed_forms(dim):
    """YADE's vertex model with bonded joints (dem_validation/job.py ``bonds``: a clamp ft' A and
    a cohesive share c' A / n on each contact's Coulomb cap) against the closed forms above,
    within 2 %: the glued block sliding at mu + c A / W = 0.503874, and the tall block with
    tension and cohesion (ft = 5,000 Pa <= c / mu = 12,500 Pa) overturning at
    (b / h)(1 + ft A / W) = 0.501937."""
    from dem_validation.api import run_scene

    res = run_scene(load_scene(_glued(dim, cohesion=2000.0)))
    assert res["status"] == "collapsed" and res["alpha"] == pytest.approx(0.503874, rel=0.02)
    res = run_scene(load_scene(_tall(dim, tensile_strength=5000.0, cohesion=10000.0)))
    assert res["status"] == "collapsed" and res["alpha"] == pytest.approx(0.501937, rel=0.02)
