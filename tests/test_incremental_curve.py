"""The capacity curve by incremental limit analysis (limit/incremental_curve.py): step 2
re-solved on the displaced geometry, sliding and mixed mechanisms included.

Closed forms (unit depth in 2D; gravity along -y in 2D, -z in 3D; horizontal body force
alpha W along +x):

* Rocking block, width b, height h, on a wider base: turned by theta about its toe, its
  centroid lies (b/2, h/2) turned by theta from the toe, so moment equilibrium about the toe
  gives alpha = tan(atan(b/h) - theta); alpha = 0 when the centroid is over the toe, after a
  horizontal centroid travel of b/2.
* Block sliding down a plane inclined at beta (downhill along +x), friction mu = tan(phi):
  along the plane W sin(beta) + alpha W cos(beta) = mu (W cos(beta) - alpha W sin(beta)), so
  alpha = (mu cos(beta) - sin(beta)) / (cos(beta) + mu sin(beta)) = tan(phi - beta), the same at
  every displacement while the block stays on the plane. In 3D the friction cone is the
  24-face pyramid inscribed in the cone (limit/model/yield_domain.py), whose friction along a
  direction lies between mu cos(pi/24) and mu.
* Block (b x h, mu < b/h) on a support whose top ends at x = b, under its right edge: it slides
  at alpha = mu until tipping about the support's edge E = (b, 0) needs less, (b - x_c) / z_c
  with (x_c, z_c) its centroid (moment about E); so at every configuration alpha = min(mu,
  (b - x_c)/z_c), and alpha = 0 when the centroid is over E: travel b/2.
"""
import numpy as np
import pytest

from limit.analysis import analyse
from limit.model.scene import load_scene
from limit.verdict.capacity_curve import follow
from limit.incremental_curve import follow_frictional
from limit.verdict.local_check import step_mechanism


def _extrude(P):
    return [[x, y, z] for y in (0.0, 1.0) for x, z in P]


def _scene(base, block, dim, mu):
    if dim == 3:
        base, block = _extrude(base), _extrude(block)
    return load_scene({"format": "blockscene/1", "dim": dim, "friction": mu,
                       "blocks": [{"id": "base", "vertices": base, "fixed": True}, {"id": "block", "vertices": block}],
                       "loads": {"live": [{"type": "body_force", "direction": [1, 0] if dim == 2 else [1, 0, 0]}]}})


def _rect(b, h, beta=0.0):
    c, s = np.cos(beta), np.sin(beta)
    return [[c * x + s * y, -s * x + c * y] for x, y in ((0, 0), (b, 0), (b, h), (0, h))]


@pytest.mark.parametrize("dim", [2, 3])
def test_a_rocking_block_follows_tan_of_its_slenderness_angle_less_its_rotation(dim):
    b, h = 0.4, 1.0
    r = follow_frictional(_scene([[-0.5, -0.3], [0.9, -0.3], [0.9, 0], [-0.5, 0]], _rect(b, h), dim, 0.6), steps=20)
    theta = np.abs(r["rotation"])
    assert r["method"] == "incremental" and len(r["alpha"]) > 10
    # the last point is moved back to alpha = 0 at d0, its rotation interpolated: checked by d0
    np.testing.assert_allclose(r["alpha"][:-1], np.tan(np.arctan(b / h) - theta[:-1]), atol=1e-6)
    assert r["d0"] == pytest.approx(b / 2, rel=1e-3)
    assert r["spectral"]["du_star"] is not None


def test_a_block_sliding_down_an_inclined_plane_keeps_tan_phi_less_beta():
    beta, mu = np.radians(10.0), 0.5
    t = np.tan(beta)
    base = [[-0.5, -2.0], [3.0, -2.0], [3.0, -3.0 * t], [-0.5, 0.5 * t]]
    r = follow_frictional(_scene(base, _rect(1.0, 0.3, beta), 2, mu), steps=6)
    np.testing.assert_allclose(r["alpha"], np.tan(np.arctan(mu) - beta), rtol=1e-6)
    assert r["d"][-1] > 0.9 and r["d0"] is None  # it slid about a metre, and alpha never fell
    assert np.abs(r["rotation"]).max() < 1e-9


def test_in_3d_the_sliding_multiplier_stays_between_the_pyramids_bounds():
    beta, mu = np.radians(10.0), 0.5
    t = np.tan(beta)
    base = [[-0.5, -2.0], [3.0, -2.0], [3.0, -3.0 * t], [-0.5, 0.5 * t]]
    r = follow_frictional(_scene(base, _rect(1.0, 0.3, beta), 3, mu), steps=4)
    a = np.array(r["alpha"])
    np.testing.assert_allclose(a, a[0], rtol=1e-6)
    lo, hi = np.tan(np.arctan(mu * np.cos(np.pi / 24)) - beta), np.tan(np.arctan(mu) - beta)
    assert lo - 1e-9 <= a[0] <= hi + 1e-9


@pytest.mark.parametrize("dim", [2, 3])
def test_a_block_slides_to_its_supports_edge_then_tips_over_it(dim):
    b, h, mu = 0.4, 1.0, 0.3
    r = follow_frictional(_scene([[-0.5, -0.3], [b, -0.3], [b, 0], [-0.5, 0]], _rect(b, h), dim, mu), steps=40)
    x, z = np.array(r["control_centroid"])[:, 0], np.array(r["control_centroid"])[:, -1]
    a = np.array(r["alpha"])
    mu_eff = a[0]  # 2D: mu; 3D: the pyramid's friction along x
    assert (mu * np.cos(np.pi / 24) - 1e-9 <= mu_eff <= mu + 1e-9) and (dim == 3 or mu_eff == pytest.approx(mu))
    np.testing.assert_allclose(a[:-1], np.minimum(mu_eff, (b - x[:-1]) / z[:-1]), atol=1e-6)
    assert (np.abs(a[:-1] - mu_eff) < 1e-9).sum() >= 3 and a[-2] < 0.5 * mu_eff  # it slid, then tipped
    assert r["d0"] == pytest.approx(b / 2, rel=1e-3)


def test_the_catalogs_wall_whose_joints_open_while_they_slide_turns_about_its_toe():
    """wall-3x3-opening-2d (its "expected" says why): blocks c1-3 (0.2 x 0.4 m, centroid (1.1,
    0.6)) and c2-2 (0.4 x 0.4 m, centroid (1.0, 1.0)) turn together about the toe (1.2, 0.4)
    while c2-2's joint with c1-2 opens and slides. Their joint centroid (1.0333, 0.8667) lies
    (-1/6, 7/15) from the toe, so alpha = tan(atan(5/14) - theta) (5/14 = (1/6)/(7/15)), and alpha
    = 0 at theta* = atan(5/14), where c2-2's centroid, (-0.2, 0.6) from the toe, has moved
    0.2 - 0.2 cos(theta*) + 0.6 sin(theta*) = 0.213453 m. The rocking follower refuses this
    mechanism (a joint slides). In 10 steps, step 2 at one configuration lands on a higher local
    state (0.82); the jump rule redoes that step at half its size."""
    sc = load_scene("scenes/catalog/wall-3x3-opening-2d.json")
    res = analyse(sc, verdict=False).data
    step, a0, mech = step_mechanism(res)
    with pytest.raises(ValueError, match="slides"):
        follow(sc, mech, a0)
    ts = np.arctan(5 / 14)
    for n in (10, 20):  # in 10 steps, step 2 misses the toe rotation once: that step is redone halved
        r = follow_frictional(sc, a0, mechanism=mech, steps=n)
        theta = np.abs(r["rotation"][:-1])  # the last point: alpha 0 at d0, checked below
        np.testing.assert_allclose(r["alpha"][:-1], np.tan(np.arctan(5 / 14) - theta), atol=1e-6)
        assert r["control"] == "c2-2"
        assert r["d0"] == pytest.approx(0.2 - 0.2 * np.cos(ts) + 0.6 * np.sin(ts), rel=1e-4)


@pytest.mark.parametrize("name", ["portal-2d", "stack-3-3d"])
def test_on_rocking_mechanisms_it_converges_to_the_kinematic_chain_follower(name):
    """A second method: limit.verdict.capacity_curve.follow follows a rocking mechanism by its
    joint equations and the work ratio, with no statics. The incremental curve (first order in
    the step) must approach it as the step shrinks."""
    sc = load_scene(f"scenes/catalog/{name}.json")
    res = analyse(sc, verdict=False).data
    _, a0, mech = step_mechanism(res)
    ref = follow(sc, mech, a0)
    err = []
    for n in (10, 40):
        r = follow_frictional(sc, a0, mechanism=mech, steps=n)
        a = np.interp(ref["d"], r["d"], r["alpha"], right=np.nan)
        err.append(float(np.nanmax(np.abs(a - np.array(ref["alpha"])))))
        assert r["d0"] == pytest.approx(ref["d0"], rel=1e-2)
    assert err[1] < 0.5 * err[0] and err[1] < 2e-4 * max(1.0, a0)


def test_ties_and_pressure_loads_are_refused_by_name():
    sc = load_scene("scenes/catalog/block-tied-2d.json")
    with pytest.raises(ValueError, match="tie rods"):
        follow_frictional(sc)


def test_the_code_check_of_a_mechanism_whose_joints_slide_gets_its_nonlinear_check():
    """The 3x3 wall with its opening (a facade with a window) under a site demand: the verdict's
    curve is the incremental one, and its du* is the closed form's. In the toe rotation
    (previous test) c1-3 and c2-2 (weights in the ratio 0.08 : 0.16) move 0.2 and 0.6 m along
    x per unit rotation, the control block is c2-2 (dx_k = 0.6), so d* = d sum P dx^2 / (dx_k sum
    P dx) = d (0.08 0.04 + 0.16 0.36) / (0.6 (0.08 0.2 + 0.16 0.6)) = 0.904762 d (Circolare
    C8A.4.5), and du* = 0.4 d0* = 0.4 x 0.904762 x 0.213453 m = 77.25 mm (C8A.4.2.3)."""
    import json

    from limit.verdict.local_check import verdict, verdict_lines

    data = json.load(open("scenes/catalog/wall-3x3-opening-2d.json"))
    data["demand"] = {"ag_g": 0.2, "F0": 2.5, "Tc_star": 0.4, "soil": "B", "q": 2.0, "fc": 1.35}
    sc = load_scene(data)
    v = verdict(sc, analyse(sc, verdict=False).data, sliding=follow_frictional)
    assert v["curve"]["method"] == "incremental" and not v["curve_reason"]
    ts = np.arctan(5 / 14)
    d0 = 0.2 - 0.2 * np.cos(ts) + 0.6 * np.sin(ts)
    du = 0.4 * (0.08 * 0.04 + 0.16 * 0.36) / (0.6 * (0.08 * 0.2 + 0.16 * 0.6)) * d0
    assert v["curve"]["spectral"]["du_star"] == pytest.approx(du, rel=1e-4)
    nl = v["check"]["nonlinear"]
    assert nl["capacity"] == pytest.approx(du, rel=1e-4) and nl["demand"] > 0
    assert any(s.startswith("Capacity curve (incremental limit analysis") for s in verdict_lines(v))


def test_limit_check_takes_the_curves_settings_and_names_a_bad_one(capsys):
    from limit.cli import main

    assert main(["check", "scenes/catalog/block-rocking-2d.json", "--set", "curve_step=3"]) == 2
    assert "unknown setting 'curve_step'" in capsys.readouterr().err
    assert main(["check", "scenes/catalog/wall-3x3-opening-2d.json", "--set", "curve_steps=10"]) == 0
    assert "Capacity curve (incremental limit analysis" in capsys.readouterr().out
