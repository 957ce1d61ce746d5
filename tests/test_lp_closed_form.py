"""The associative LP against closed-form collapse factors, 2D and 3D, to 1e-6."""
import math

import numpy as np
import pytest

from limit.solve import mechanism
from scenes import builders as B
from tests import lp_helpers
from tests.lp_helpers import lp_alpha

RTOL = 1e-6
MODELS = ["paper", "vertex"]


@pytest.fixture(autouse=True, params=["clarabel", "ipm"])
def lp_solver(request, monkeypatch):
    """Every closed form is checked with Clarabel (via cvxpy) and with the structured interior point method."""
    monkeypatch.setattr(lp_helpers, "SOLVER", request.param)
    return request.param


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("dim", [2, 3])
def test_single_block_rocking(dim, model):
    b, h = 0.3, 1.2
    a, sol, _, P = lp_alpha(B.single_block(dim=dim, b=b, h=h, t=0.5, mu=0.9), model=model)
    assert a == pytest.approx(b / h, rel=RTOL)
    cls = mechanism.classify(P, sol.u)
    assert cls["rock"].all() and not cls["slide"].any()


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("dim", [2, 3])
def test_single_block_sliding(dim, model):
    mu = 0.35
    a, sol, _, P = lp_alpha(B.single_block(dim=dim, b=1.0, h=0.5, t=1.0, mu=mu), model=model)
    assert a == pytest.approx(mu, rel=RTOL)
    assert mechanism.classify(P, sol.u)["slide"].all()


@pytest.mark.parametrize("dim", [2, 3])
def test_two_stacked_blocks(dim):
    b, h = 0.3, 0.5
    a, *_ = lp_alpha(B.stack(2, dim=dim, b=b, h=h, mu=0.9))
    assert a == pytest.approx(b / (2 * h), rel=RTOL)


@pytest.mark.parametrize("dim", [2, 3])
def test_live_load_on_top_block_by_tag(dim):
    # Only the top block (tag 'top') is pushed: the whole stack overturns about the base toe,
    # alpha W (1.5 h) = 2 W (b / 2)  ->  alpha = 2 b / (3 h); the top block alone needs b / h.
    b, h = 0.3, 0.5
    d = B.stack(2, dim=dim, b=b, h=h, mu=0.9)
    d["loads"]["live"] = [{"type": "body_force", "direction": [1.0] + [0.0] * (dim - 1), "blocks": {"tags": ["top"]}}]
    a, *_ = lp_alpha(d)
    assert a == pytest.approx(2 * b / (3 * h), rel=RTOL)


@pytest.mark.parametrize("dim", [2, 3])
def test_weak_joint_slides_first(dim):
    d = B.stack(2, dim=dim, b=0.6, h=0.5, mu=0.9)
    d.setdefault("interfaces", {})["friction"] = [{"blocks": ["s0", "s1"], "mu": 0.1}]  # keeps the builder's model
    a, sol, _, P = lp_alpha(d)
    assert a == pytest.approx(0.1, rel=RTOL)
    cls = mechanism.classify(P, sol.u)
    pairs = P.I.pairs(P.scene)
    assert cls["slide"][pairs.index(("s0", "s1"))]
    assert not cls["slide"][pairs.index(("base", "s0"))]


@pytest.mark.parametrize("dim", [2, 3])
def test_point_force_at_the_top(dim):
    # Horizontal force F = W at the top centre: alpha F h = W b / 2  ->  alpha = b / (2 h).
    b, h, t = 0.4, 1.0, 0.5
    d = B.single_block(dim=dim, b=b, h=h, t=t, mu=0.9)
    W = 2000 * b * h * (t if dim == 3 else 1.0) * 9.81
    top = [b / 2, h] if dim == 2 else [b / 2, t / 2, h]
    d["loads"]["live"] = [{"type": "point_force", "block": "block", "force": [W] + [0.0] * (dim - 1), "point": top}]
    a, *_ = lp_alpha(d)
    assert a == pytest.approx(b / (2 * h), rel=RTOL)


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("dim", [2, 3])
def test_portal_with_lintel(dim, model):
    # Sway mechanism: columns rock about their toes, the lintel translates: alpha = b / h.
    b, h = 0.3, 1.5
    a, sol, _, P = lp_alpha(B.portal(dim=dim, col_b=b, col_h=h, span=1.0, lintel_h=0.3, mu=0.9), model=model)
    assert a == pytest.approx(b / h, rel=RTOL)


@pytest.mark.parametrize("model", MODELS)
def test_3d_running_bond_wall_out_of_plane(model):
    # Overturning of the whole wall about its base edge under a body force across it: alpha = t / H.
    courses, T, H = 6, 0.2, 0.175
    d = B.running_bond_wall(courses, 4, dim=3, L=0.4, H=H, T=T, mu=0.9)
    d["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]
    a, sol, _, P = lp_alpha(d, model=model)
    assert a == pytest.approx(T / (courses * H), rel=RTOL)


def oblique_alpha(half_x, half_y, h, theta):
    """Least b_e / ((h / 2) d . n_e) over the base edges of a block with half sides half_x, half_y."""
    d = np.array([math.cos(theta), math.sin(theta)])
    best = math.inf
    for n, dist in (([1, 0], half_x), ([-1, 0], half_x), ([0, 1], half_y), ([0, -1], half_y)):
        dn = d @ n
        if dn > 1e-12:
            best = min(best, dist / (h / 2 * dn))
    return best


@pytest.mark.parametrize("theta_deg", [0.0, 20.0, 45.0, 70.0])
def test_3d_block_oblique_load(theta_deg):
    bx, by, h = 0.4, 0.25, 1.0
    th = math.radians(theta_deg)
    d = B.single_block(dim=3, b=bx, h=h, t=by, mu=2.0)
    d["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    a, *_ = lp_alpha(d)
    assert a == pytest.approx(oblique_alpha(bx / 2, by / 2, h, th), rel=RTOL)


@pytest.mark.parametrize("angle", [30.0, -65.0])
def test_rotated_box(angle):
    # A box turned about the vertical on a wide base, pushed along x: the oblique formula in its own axes.
    bx, by, h = 0.4, 0.25, 1.0
    d = B.single_block(dim=3, b=bx, h=h, t=by, mu=2.0)
    d["blocks"][0]["box"]["size"] = [4.0, 4.0, 0.2]
    d["blocks"][0]["box"]["center"] = [0.0, 0.0, -0.1]
    d["blocks"][1]["box"] = {"center": [0.0, 0.0, h / 2], "size": [bx, by, h],
                             "rotation": {"axis": [0, 0, 1], "angle_deg": angle}}
    a, *_ = lp_alpha(d)
    assert a == pytest.approx(oblique_alpha(bx / 2, by / 2, h, math.radians(-angle)), rel=RTOL)


def test_rotated_box_2d_lying():
    # A 2D box given upright but turned by 90 degrees lies down: b and h swap (mu high enough not to slide).
    d = B.single_block(dim=2, b=0.3, h=1.2, mu=5.0)
    d["blocks"][1]["box"] = {"center": [0.6, 0.15], "size": [0.3, 1.2], "rotation": {"angle_deg": 90}}
    d["blocks"][0]["box"]["size"] = [3.0, 0.2]
    a, *_ = lp_alpha(d)
    assert a == pytest.approx(1.2 / 0.3, rel=RTOL)
