"""Linear kinematic analysis (limit/verdict/kinematic_check.py) against hand computations.

Closed forms, with horizontal virtual displacements dx_i of the weights P_i:
M* = (sum P_i dx_i)^2 / (g sum P_i dx_i^2), e* = g M* / sum P_i, a0* = alpha0 g / (e* FC).

* One block (mass m) turning about its toe: one weight, so M* = (P dx)^2 / (g P dx^2) = P/g
  = m and e* = 1, whatever dx; a0* = alpha0 g / FC.
* Two equal blocks b x h (mass m each) stacked, turning together about the base toe by a
  small angle w: their centroids, at heights h/2 and 3h/2, move horizontally by w h/2 and
  3 w h/2. M* = (m g w (h/2 + 3h/2))^2 / (g m g w^2 (h^2/4 + 9h^2/4)) = m 4h^2 / (10 h^2/4)
  = 1.6 m; e* = g 1.6 m / (2 m g) = 0.8. The LP finds that mechanism: the whole stack
  overturns at alpha = b / (2h) (moments about the toe: alpha 2W h = 2W b/2), below the top
  block alone (alpha = b/h).
"""
import math

import numpy as np
import pytest

from limit import analyse, load_scene
from limit.verdict.kinematic_check import linear
from scenes import builders as B

G = 9.81


@pytest.mark.parametrize("dim", [2, 3])
def test_one_block_has_all_its_mass_participating(dim):
    scene = load_scene(B.single_block(dim, 0.3, 1.0, mu=0.8))
    r = analyse(scene, method="lp")
    assert r.lp.alpha == pytest.approx(0.3, rel=1e-6)
    q = linear(scene, r.lp.mechanism, r.lp.alpha, fc=1.35)
    m = scene.blocks[int(scene.free[0])].mass
    assert q["M_star"] == pytest.approx(m, rel=1e-9)
    assert q["e_star"] == pytest.approx(1.0, rel=1e-9)
    assert q["a0_star"] == pytest.approx(0.3 * G / 1.35, rel=1e-6)
    assert q["a0_star_g"] == pytest.approx(0.3 / 1.35, rel=1e-6)


@pytest.mark.parametrize("dim", [2, 3])
def test_two_stacked_blocks_turning_together(dim):
    b, h = 0.3, 0.5
    scene = load_scene(B.stack(2, dim, b=b, h=h, mu=0.8))
    r = analyse(scene, method="lp")
    assert r.lp.alpha == pytest.approx(b / (2 * h), rel=1e-6)
    q = linear(scene, r.lp.mechanism, r.lp.alpha, fc=1.0)
    m = scene.blocks[int(scene.free[0])].mass
    assert q["M_star"] == pytest.approx(1.6 * m, rel=1e-6)
    assert q["e_star"] == pytest.approx(0.8, rel=1e-6)
    assert q["a0_star"] == pytest.approx(b / (2 * h) * G / 0.8, rel=1e-6)
    assert q["n_weights"] == 2


def test_a_hand_mechanism_only_moving_weights_count():
    """Top block of two turning alone about the joint's toe (b/2, h): one weight moves, so
    M* = m and e* = 1 (the still block's weight is not part of the chain)."""
    b, h = 0.3, 0.5
    scene = load_scene(B.stack(2, 2, b=b, h=h, mu=0.8))
    top = scene.blocks[int(scene.free[1])]
    w = -1.0  # clockwise about the toe: centroid velocity w x (c - toe)
    r = top.centroid - np.array([b, h])  # builder blocks span x in [0, b]
    mech = {scene.blocks[int(scene.free[0])].id: [0.0, 0.0, 0.0],
            top.id: [-w * r[1], w * r[0], w]}
    q = linear(scene, mech, 0.6)
    assert q["M_star"] == pytest.approx(top.mass) and q["e_star"] == pytest.approx(1.0) and q["n_weights"] == 1


def test_bad_inputs_are_named():
    scene = load_scene(B.single_block(2))
    with pytest.raises(ValueError, match="confidence factor"):
        linear(scene, {"block": [1.0, 0.0, 0.0]}, 0.3, fc=0.5)
    with pytest.raises(ValueError, match="moves no weight"):
        linear(scene, {"block": [0.0, 0.0, 0.0]}, 0.3)
    with pytest.raises(ValueError, match="only vertically"):
        linear(scene, {"block": [0.0, 1.0, 0.0]}, 0.3)
    assert math.isfinite(linear(scene, {"block": [1.0, 0.0, 0.0]}, 0.3)["M_star"])


# ------------------------------------------------------------------ nonlinear (capacity curve)

def test_block_turning_about_its_toe_follows_tan_closed_form():
    """A block b x h turned by theta about its toe: its centroid's lever about the toe is
    (h/2) sin(phi0 - theta) horizontally and (h/2)... so alpha W (vertical lever) = W
    (horizontal lever) gives alpha(theta) = tan(atan(b/h) - theta), zero at theta0 =
    atan(b/h), where the centroid has moved b/2 sideways (d0 = b/2)."""
    from limit.verdict.capacity_curve import follow

    b, h = 0.3, 1.0
    scene = load_scene(B.single_block(2, b, h, mu=0.8))
    r = analyse(scene, method="lp")
    out = follow(scene, r.lp.mechanism, r.lp.alpha, steps=300)
    th = -np.array(out["rotation"])  # clockwise
    a = np.array(out["alpha"])
    pos = a > 0
    assert np.max(np.abs(a[pos] - np.tan(math.atan(b / h) - th[pos]))) < 1e-6
    assert out["d0"] == pytest.approx(b / 2, rel=1e-6)
    sp = out["spectral"]  # one block: e* = 1, d* = d
    assert sp["e_star"] == pytest.approx(1.0) and sp["d0_star"] == pytest.approx(b / 2, rel=1e-6)
    assert sp["du_star"] == pytest.approx(0.4 * b / 2, rel=1e-6)


def test_two_blocks_turning_together_about_the_base_toe():
    """Two stacked blocks b x h as one body of height H = 2h: alpha(theta) = tan(atan(b/H)
    - theta); the control point (top centroid, at (-b/2, 3h/2) from the toe) has moved
    b/2 (1 - cos theta0) + (3h/2) sin theta0 sideways when alpha reaches 0."""
    from limit.verdict.capacity_curve import follow

    b, h = 0.3, 0.5
    scene = load_scene(B.stack(2, 2, b=b, h=h, mu=0.8))
    r = analyse(scene, method="lp")
    out = follow(scene, r.lp.mechanism, r.lp.alpha, steps=300)
    th, a = -np.array(out["rotation"]), np.array(out["alpha"])
    pos = a > 0
    assert np.max(np.abs(a[pos] - np.tan(math.atan(b / (2 * h)) - th[pos]))) < 1e-6
    t0 = math.atan(b / (2 * h))
    assert out["d0"] == pytest.approx(b / 2 * (1 - math.cos(t0)) + 1.5 * h * math.sin(t0), rel=1e-6)


@pytest.mark.parametrize("case", ["block", pytest.param("wall", marks=pytest.mark.slow)])  # wall: about 11 s
def test_3d_rocking_follows_the_tan_closed_form(case):
    """3D: a block b x h (depth 0.5) turning about its base edge, and the catalog's running-
    bond wall (24 blocks, t = 0.2 m, H = 1.05 m, loaded out of plane) turning as one body
    about its base edge: the same plane geometry as the 2D block, alpha(theta) =
    tan(atan(t/H) - theta), with theta the rotation's magnitude (the 3D follower's
    "rotation"), zero at d0 = t/2 for the block."""
    from limit.verdict.capacity_curve import follow
    from scenes.catalog import CATALOG_DIR

    if case == "block":
        b, H = 0.3, 1.0
        scene = load_scene(B.single_block(3, b, H, t=0.5, mu=0.8))
    else:
        b, H = 0.2, 1.05
        scene = load_scene(str(CATALOG_DIR / "wall-out-of-plane-3d.json"))
    r = analyse(scene, method="lp")
    out = follow(scene, r.lp.mechanism, r.lp.alpha, steps=150)
    th, a = np.array(out["rotation"]), np.array(out["alpha"])
    pos = a > 0
    assert pos.sum() > 50 and th[pos].max() > 0.9 * math.atan(b / H)
    assert np.max(np.abs(a[pos] - np.tan(math.atan(b / H) - th[pos]))) < 1e-6
    if case == "block":
        assert out["d0"] == pytest.approx(b / 2, rel=1e-6)


@pytest.mark.parametrize("dim", [2, 3])
def test_portal_sway_follows_its_closed_form(dim):
    """The catalog portal: columns b x h = 0.3 x 1.5 turning clockwise by theta about their
    right toes, the lintel translating with their top-left corners (a parallelogram). From
    the toe, a column's centroid is at (-b/2 cos + h/2 sin, b/2 sin + h/2 cos) and its top-left
    corner at (-b cos + h sin, b sin + h cos) (theta's cos, sin). Virtual work, weights W_c
    (each column) and W_L (lintel): alpha (2 W_c dx_c' + W_L dx_L') = 2 W_c dy_c' + W_L dy_L'
    with dx_c' = (b sin + h cos)/2, dy_c' = (b cos - h sin)/2, and twice those for the lintel,
    so alpha(theta) = (b cos - h sin) / (b sin + h cos) = tan(atan(b/h) - theta) whatever the
    weights. The control point is the lintel's centroid (largest motion): d(theta) =
    b (1 - cos theta) + h sin theta, so d0 = b at theta0 = atan(b/h)."""
    from scipy.optimize import brentq

    from limit.verdict.capacity_curve import follow
    from scenes.catalog import CATALOG_DIR

    b, h = 0.3, 1.5
    scene = load_scene(str(CATALOG_DIR / f"portal-{dim}d.json"))
    r = analyse(scene, method="lp")
    out = follow(scene, r.lp.mechanism, r.lp.alpha, steps=200)
    assert out["control"] == "lintel"
    d, a = np.array(out["d"]), np.array(out["alpha"])
    th = np.array([brentq(lambda t: b * (1 - math.cos(t)) + h * math.sin(t) - x, -0.1, 1.0) for x in d])
    pos = a > 0
    assert np.max(np.abs(a[pos] - np.tan(math.atan(b / h) - th[pos]))) < 1e-6
    assert out["d0"] == pytest.approx(b, rel=1e-6)


def test_a_sliding_mechanism_is_refused_naming_the_joint():
    from limit.verdict.capacity_curve import follow

    scene = load_scene(B.single_block(2, 1.0, 0.5, mu=0.4))
    r = analyse(scene, method="lp")
    with pytest.raises(ValueError, match="base\\|block slides"):
        follow(scene, r.lp.mechanism, r.lp.alpha)


# ------------------------------------------------------------------ demand and the check

def test_spectrum_by_hand_and_the_linear_check():
    """ag = 0.25 g, S = 1.2, F0 = 2.5, TB/TC/TD = 0.15/0.5/2 s: plateau 0.25 9.81 1.2 2.5 =
    7.3575 m/s^2; Se(0) = ag S = 2.943; Se(1) = 7.3575 0.5 / 1 = 3.67875; Se(4) = 7.3575 0.5 2 / 16
    = 0.45984. One block (e* = 1) with alpha0 = 0.3, FC = 1.35: a0* = 0.3 9.81 / 1.35 =
    2.18 m/s^2 against ag S / q = 0.25 9.81 1.2 / 2 = 1.4715 at ground level: passes, ratio
    1.4815. With its base at Z = 6 m of a 9 m, 3-storey building (T1 = 0.3 s, on the plateau):
    7.3575 (6/9) (9/7) / 2 = 3.1532 m/s^2: fails."""
    from limit.model.seismic_demand import Demand, check

    d = Demand(ag_g=0.25, S=1.2)
    assert d.Se(0.0) == pytest.approx(2.943) and d.Se(0.3) == pytest.approx(7.3575)
    assert d.Se(1.0) == pytest.approx(3.67875) and d.Se(4.0) == pytest.approx(0.459844, rel=1e-5)
    assert d.Se(0.15 - 1e-12) == pytest.approx(d.Se(0.15)) and d.Se(0.5 - 1e-12) == pytest.approx(d.Se(0.5))
    assert d.SDe(1.0) == pytest.approx(3.67875 / (4 * math.pi ** 2))
    a0 = 0.3 * G / 1.35
    c = check(d, a0)
    assert c["linear"]["pass"] and c["linear"]["ratio"] == pytest.approx(a0 / 1.4715)
    up = check(Demand(ag_g=0.25, S=1.2, Z=6.0, H=9.0, N=3, T1=0.3), a0)
    assert not up["linear"]["pass"] and up["linear"]["demand"] == pytest.approx(7.3575 * (6 / 9) * (9 / 7) / 2)
    with pytest.raises(ValueError, match="demand.ag_g"):
        Demand(ag_g=-0.1)
    with pytest.raises(ValueError, match="above ground"):
        Demand(ag_g=0.1, Z=3.0)


def test_nonlinear_check_of_one_block():
    """The block b x h = 0.3 x 1 about its toe: d0* = b/2 = 0.15 m (e* = 1, d* = d),
    du* = 0.4 d0* = 0.06 m, ds* = 0.024 m where a* = tan(phi0 - theta) g / FC with the centroid
    moved 0.024 m; Ts = 2 pi sqrt(ds*/as*). Demand SDe(Ts) from the spectrum."""
    from limit.verdict.capacity_curve import follow
    from limit.model.seismic_demand import Demand, check

    scene = load_scene(B.single_block(2, 0.3, 1.0, mu=0.8))
    r = analyse(scene, method="lp")
    sp = follow(scene, r.lp.mechanism, r.lp.alpha, steps=300)["spectral"]
    assert sp["du_star"] == pytest.approx(0.06, rel=1e-6) and sp["ds_star"] == pytest.approx(0.024, rel=1e-6)
    # centroid at (-0.15, 0.5) from the toe moves 0.024 sideways: solve for theta
    phi0 = math.atan(0.3)
    R = math.hypot(0.15, 0.5)
    th = phi0 - math.asin((0.15 - 0.024) / R)  # its horizontal lever to the toe is then 0.15 - 0.024
    as_ = math.tan(phi0 - th) * G / 1.35
    assert sp["as_star"] == pytest.approx(as_, rel=1e-4)
    assert sp["Ts"] == pytest.approx(2 * math.pi * math.sqrt(0.024 / as_), rel=1e-4)
    d = Demand(ag_g=0.25, S=1.2)
    c = check(d, 0.3 * G / 1.35, sp["du_star"], sp["Ts"])
    assert c["nonlinear"]["demand"] == pytest.approx(d.SDe(sp["Ts"])) and c["nonlinear"]["pass"] == (0.06 >= d.SDe(sp["Ts"]))


def test_floor_spectrum_above_ground_by_hand():
    """Circolare 2019 [C7.2.5]-[C7.2.10], first mode; ag 0.25 g, S 1.2 (plateau 7.3575 m/s^2),
    base at Z = 6 m of a 9 m, 3-storey building, T1 = 0.3 s; building damping xi1 = 5 %
    (eta 1), mechanism xi = 8 % (eta = sqrt(10/13)):
    aZ = 7.3575 (9/7)(6/9) sqrt(1 + 0.0004 5^2) = 7.3575 (6/7) sqrt(1.01);
    A = 1.1 / sqrt(0.05) sqrt(10/13) (xi1 as a fraction, see seismic_demand's docstring).
    T = 0: A aZ / (1 + (A - 1)) = aZ, the floor's own peak acceleration; plateau A aZ on
    [0.8 T1, 1.1 T1) = [0.24, 0.33); T = 0.12: A aZ / (1 + (A - 1) 0.5^1.6); T = 0.66 = 2 b T1:
    A aZ / (1 + (A - 1) 1) = aZ (above the ground's 7.3575 sqrt(10/13) 0.5/0.66 = 4.889);
    T = 3 s: the formula's A aZ / (1 + (A - 1) (3/0.33 - 1)^1.2) = 0.655 is below the ground's
    Se(3, 8 %) = 7.3575 sqrt(10/13) 0.5 2 / 9 = 0.717, which [C7.2.5] keeps. Displacement
    ([C8.7.1.12]) at 0.66 s: aZ 0.66^2 / 4 pi^2 = 0.4356 aZ / 4 pi^2 is below the value held from
    b T1, A aZ 0.33^2 / 4 pi^2 = 0.4699 aZ / 4 pi^2, which is kept. The unit of xi1: at 5 % for
    both dampings A = 4.92, the a_p = 5.0 of the same section's simplified floor spectrum
    [C7.2.11] (Table C7.2.II, T1 < 0.5 s); xi1 in percent would give 0.49."""
    from limit.model.seismic_demand import Demand, eta_of

    d = Demand(ag_g=0.25, S=1.2, Z=6.0, H=9.0, N=3, T1=0.3)
    aZ = 7.3575 * (6 / 7) * math.sqrt(1.01)
    A = 1.1 / math.sqrt(0.05) * math.sqrt(10 / 13)
    assert eta_of(0.08) == pytest.approx(math.sqrt(10 / 13)) and eta_of(0.5) == 0.55
    assert d.floor_peak() == pytest.approx(aZ) and d.floor_amplification() == pytest.approx(A)
    assert d.SeZ(0.0) == pytest.approx(aZ)
    assert d.SeZ(0.24) == pytest.approx(A * aZ) and d.SeZ(0.33 - 1e-12) == pytest.approx(A * aZ)
    assert d.SeZ(0.12) == pytest.approx(A * aZ / (1 + (A - 1) * 0.5 ** 1.6))
    assert d.SeZ(0.66) == pytest.approx(aZ)
    assert d.SeZ(3.0) == pytest.approx(7.3575 * math.sqrt(10 / 13) * 0.5 * 2 / 9)
    assert A * aZ / (1 + (A - 1) * (3 / 0.33 - 1) ** 1.2) < d.SeZ(3.0)
    assert d.SDeZ(0.66) == pytest.approx(A * aZ * 0.33 ** 2 / (4 * math.pi ** 2))
    assert d.SDeZ(0.3) == pytest.approx(A * aZ * 0.3 ** 2 / (4 * math.pi ** 2))
    a5 = Demand(ag_g=0.25, Z=6.0, H=9.0, N=3, T1=0.3, xi_mech=0.05).floor_amplification()
    assert a5 == pytest.approx(5.0, rel=0.02)
    with pytest.raises(ValueError, match="xi1"):
        Demand(ag_g=0.25, Z=6.0, H=9.0, N=3, T1=0.3, xi1=5.0)


def test_nonlinear_check_of_one_block_above_ground():
    """The block b x h = 0.3 x 1 about its toe (e* = 1, d* = d): du* = 0.4 d0* = 0.06 m, where the
    centroid's lever to the toe is 0.15 - 0.06 = 0.09 m, so alpha = tan(asin(0.09 / R)),
    R = hypot(0.15, 0.5), and a*(du*) = alpha g / 1.35; T_SLV = 1.68 pi sqrt(0.06 / a*(du*))
    ([C8.7.1.10]). With its base at Z = 6 m of a 9 m, 3-storey building (T1 = 0.3 s) the
    demand is the floor displacement spectrum at T_SLV (checked by hand in the test above)."""
    from limit.verdict.capacity_curve import follow
    from limit.model.seismic_demand import Demand, check

    scene = load_scene(B.single_block(2, 0.3, 1.0, mu=0.8))
    r = analyse(scene, method="lp")
    sp = follow(scene, r.lp.mechanism, r.lp.alpha, steps=300)["spectral"]
    au = math.tan(math.asin(0.09 / math.hypot(0.15, 0.5))) * G / 1.35
    assert sp["au_star"] == pytest.approx(au, rel=1e-4)
    d = Demand(ag_g=0.25, S=1.2, Z=6.0, H=9.0, N=3, T1=0.3)
    c = check(d, 0.3 * G / 1.35, sp["du_star"], sp["Ts"], sp["au_star"])
    T = 1.68 * math.pi * math.sqrt(0.06 / au)
    nl = c["nonlinear"]
    assert nl["period"] == pytest.approx(T, rel=1e-4) and nl["demand"] == pytest.approx(d.SDeZ(T), rel=1e-4)
    assert nl["pass"] == (0.06 >= d.SDeZ(T)) and nl["ratio"] == pytest.approx(0.06 / d.SDeZ(T), rel=1e-4)
    assert check(d, 1.0, sp["du_star"], sp["Ts"])["nonlinear"] is None  # no a*(du*): not made, with the reason
