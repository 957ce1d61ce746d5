"""Crushing: a joint's compressive strength fc (the scene's ``joints`` groups) moves the hinge
inwards (limit/model/yield_domain.py, ``crushing_chords``). A 0.4 m wide, 1.0 m tall block (0.3 m
deep in 3D; density 2000 kg/m^3, g = 9.81 m/s^2, a 2D scene 1 m thick) on a fixed base, mu 0.9,
under a horizontal body force.

Closed form: the base carries N = W as a stress block fc over a depth W / (fc t) at the toe, so
the weight's lever about it is b/2 - W / (2 fc t), and alpha W h/2 = W (b/2 - W / (2 fc t)):
alpha = (b - W / (fc t)) / h."""
import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.model.assemble import Options
from limit.model.scene import load_scene
from limit.model.yield_domain import CRUSH_CHORDS, crushing_chords
from scenes import builders as B

RHO_G = 2000.0 * 9.81


def _block(dim, **joint):
    d = B.single_block(dim=dim, b=0.4, h=1.0, t=0.3 if dim == 3 else None, mu=0.9)
    d["joints"] = [{"between": {"blocks": ["base", "block"]}, **joint}]
    return d


def _t(dim):
    return 1.0 if dim == 2 else 0.3


@pytest.mark.parametrize("dim", [2, 3])
def test_crushing_at_a_chord_node_gives_the_closed_form(dim):
    """fc = 10 W / (4 A): N = W is 4/10 of N_max = fc A, a node of the chords, where they are exact:
    alpha = (b - W / (fc t)) / h = 0.4 - 0.4 x 4 / 10 = 0.24."""
    t = _t(dim)
    W, A = RHO_G * 0.4 * t, 0.4 * t
    fc = 10 * W / (4 * A)
    res = analyse(load_scene(_block(dim, fc=fc)), method="nlp").data
    want = (0.4 - W / (fc * t)) / 1.0
    assert want == pytest.approx(0.24, rel=1e-12)
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)


@pytest.mark.parametrize("dim", [2, 3])
def test_between_nodes_the_chords_are_safe_and_within_their_bound(dim):
    """fc = 50 kPa: N / N_max = W / (fc A) = 0.3924, between nodes. The chords lie inside the
    parabola, by at most f_max / n^2 = (b/2)(fc A)/4 / n^2 of moment, so alpha is below the closed
    form 0.24304 (2D) by at most that over W h/2."""
    t = _t(dim)
    W, A = RHO_G * 0.4 * t, 0.4 * t
    fc = 50000.0
    a = analyse(load_scene(_block(dim, fc=fc)), method="lp").data["lp"]["alpha"]
    exact = (0.4 - W / (fc * t)) / 1.0
    gap = 0.2 * fc * A / 4 / CRUSH_CHORDS ** 2 / (W * 0.5)
    assert exact - gap <= a <= exact * (1 + 1e-9)


def test_the_chords_bound():
    """The largest shortfall of the chords below f(N) = b N - N^2 / (2 fc L) is f_max / n^2, met at
    the middle of each step (the parabola's sagitta (N_max / n)^2 / (8 fc L))."""
    b, fcL = 0.2, 3e4
    s, c = crushing_chords(b, fcL)
    Nm = 2 * fcL * b
    N = 0.5 * Nm / s.size  # mid-step of the first chord
    f = b * N - N * N / (2 * fcL)
    assert f - (s[0] * N + c[0]) == pytest.approx(b * Nm / 4 / s.size ** 2, rel=1e-9)


def test_a_dead_load_above_the_crushing_force_collapses_under_itself():
    """fc A < W: the base cannot carry the weight at all, so the LP is infeasible."""
    W, A = RHO_G * 0.4, 0.4
    res = analyse(load_scene(_block(2, fc=0.9 * W / A)), method="lp").data
    assert res["lp"]["status"] == "infeasible"


def test_crushing_with_tension_or_on_point_contacts_is_rejected():
    with pytest.raises(SceneError, match="both fc and tensile_strength"):
        analyse(load_scene(_block(2, fc=1e5, tensile_strength=100.0)), method="lp")
    with pytest.raises(SceneError, match="paper's interface model only"):
        analyse(load_scene(_block(2, fc=1e5)), method="lp", options=Options(model="vertex"))


def test_the_catalog_pier_reaches_the_ntc_flexural_capacity():
    """scenes/catalog/pier-crushing-ntc-2d.json against NTC 2018 section 7.8.2.2.1, eq. (7.8.2):
    Mu = (l^2 t sigma0 / 2)(1 - sigma0 / (0.85 fd)). l = 1.2 m, t = 0.3 m, N = 122,400 N at the
    base (self weight 19,070.64 N plus the floor load), sigma0 = N / (l t) = 340,000 Pa, fd = 2 MPa,
    0.85 fd = 1.7 MPa: Mu = (1.44 x 0.3 x 340,000 / 2)(1 - 0.2) = 73,440 x 0.8 = 58,752 N m. The
    10 kN live load at the top (3.0 m) rocks the pier at alpha = 58,752 / 30,000 = 1.9584, in
    both steps (rocking only: step 2 keeps the LP's point)."""
    from scenes.catalog import CATALOG_DIR

    res = analyse(load_scene(str(CATALOG_DIR / "pier-crushing-ntc-2d.json")), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(1.9584, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(1.9584, rel=1e-6)
