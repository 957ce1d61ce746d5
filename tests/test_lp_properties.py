"""Duality, interface-model agreement and invariance of the associative LP."""
import json

import numpy as np
import pytest

from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.solve.lp import kinematic_lp
from limit.model.scene import load_scene
from scenes import builders as B
from scenes.catalog import catalog_files
from scenes.transform import random_rotation, reorder, transform
from tests.conftest import catalog_params
from tests.lp_helpers import lp_alpha

CATALOG = catalog_files()


@pytest.mark.parametrize("path", catalog_params(CATALOG))  # a catalog sweep: FAST_CATALOG in the fast subset
def test_static_equals_kinematic_on_catalog(path):
    d = json.loads(path.read_text())
    if d["name"] == "paper-fig2a-double-arch-2d":
        # collapses under its own weight (the paper's texture that cannot carry its arches): both LPs
        # agree on the negative alpha the static one reports as "infeasible"
        P = assemble(load_scene(d))
        sol, attempts, _ = solve_lp(P, "clarabel", fallback=False)
        assert sol.status == "infeasible" and attempts[0]["alpha"] < 0
        kin = kinematic_lp(P, "clarabel")
        assert kin.alpha == pytest.approx(attempts[0]["alpha"], rel=1e-6)
        return
    if d["name"] == "confined-block-2d":
        # no mechanism: the static LP is unbounded, and the kinematic LP has no finite alpha either
        P = assemble(load_scene(d))
        sol, _, _ = solve_lp(P, "clarabel", fallback=False)
        kin = kinematic_lp(P, "clarabel")
        assert sol.status == "unbounded" and kin.status in ("infeasible", "unbounded") and kin.alpha is None
        return
    a, sol, res, P = lp_alpha(d, check_kinematic=True)
    assert res["kinematic_lp_status"] == "optimal"
    assert res["alpha_kinematic_lp"] == pytest.approx(a, rel=1e-6, abs=1e-9)
    # and the mechanism read from the static LP's multipliers does the same work
    assert res["alpha_kinematic"] == pytest.approx(a, rel=1e-6, abs=1e-9)


def out_of_plane_wall():
    d = B.running_bond_wall(5, 4, dim=3, mu=0.9)
    d["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]
    return d


# Scenes whose collapse is by rocking alone (friction high enough never to govern).
ROCKING = {
    "block-2d": B.single_block(dim=2, b=0.3, h=1.0, mu=0.9),
    "block-3d": B.single_block(dim=3, b=0.3, h=1.0, t=0.4, mu=0.9),
    "stack-2d": B.stack(3, dim=2, b=0.3, h=0.4, mu=0.9),
    "stack-3d": B.stack(3, dim=3, b=0.3, h=0.4, mu=0.9),
    "portal-2d": B.portal(dim=2, mu=0.9),
    "portal-3d": B.portal(dim=3, mu=0.9),
    "arch-2d": B.arch(9, R=1.0, t=0.15, dim=2, mu=0.9),
    "arch-3d": B.arch(7, R=1.5, t=0.2, span_deg=120, dim=3, mu=0.9),
    "wall-out-of-plane-3d": out_of_plane_wall(),
}


@pytest.mark.parametrize("name", list(ROCKING))
def test_interface_models_agree_on_rocking(name):
    a_paper, sol, _, P = lp_alpha(ROCKING[name], model="paper")
    a_vertex, *_ = lp_alpha(ROCKING[name], model="vertex")
    assert a_vertex == pytest.approx(a_paper, rel=1e-6)


INVARIANCE = {
    "wall-out-of-plane-3d": out_of_plane_wall(),
    "arch-3d": B.arch(7, R=1.5, t=0.2, span_deg=120, dim=3, mu=0.6),
    "corner-walls-3d": B.corner_walls(courses=3, len_a=3, len_b=2, mu=0.6),
    "wall-2d": B.running_bond_wall(4, 4, dim=2, mu=0.5),
    "arch-2d": B.arch(9, R=1.0, t=0.15, dim=2, mu=0.6),
}


def rotation_about_vertical(dim, rng):
    if dim == 2:
        return np.diag([-1.0, 1.0])  # the only other 2D map keeping the vertical: a mirror
    from limit.geom.geometry import rotation_matrix

    return rotation_matrix(3, float(rng.uniform(0, 360)), [0, 0, 1])


@pytest.mark.parametrize("name", list(INVARIANCE))
def test_alpha_invariant_to_motion_scale_and_order(name):
    rng = np.random.default_rng(7)
    d = INVARIANCE[name]
    a0, *_ = lp_alpha(d)
    dim = d["dim"]
    R = rotation_about_vertical(dim, rng)
    t = rng.uniform(-50, 50, dim)
    variants = {
        "rotated": transform(d, R=R),
        "translated": transform(d, t=t),
        "scaled x1000": transform(d, s=1000.0),
        "reordered": reorder(d, seed=3),
        "all": reorder(transform(d, R=R, t=t, s=1000.0), seed=5),
    }
    for label, v in variants.items():
        a, *_ = lp_alpha(v)
        assert a == pytest.approx(a0, rel=1e-6), label


def test_alpha_invariant_to_full_rotation_3d():
    """A 3D scene turned about any axis, with its gravity turned the same way."""
    rng = np.random.default_rng(11)
    d = out_of_plane_wall()
    a0, *_ = lp_alpha(d)
    a, *_ = lp_alpha(transform(d, R=random_rotation(3, rng), t=[3, -4, 5]))
    assert a == pytest.approx(a0, rel=1e-6)


def test_block_equilibrium_weighs_a_moment_by_the_block_size():
    """verify.block_equilibrium on a block b x h (2D, weight W, live load alpha W horizontal at
    its centroid) on a fixed base: at the LP's answer the block is in balance; a moment dM added
    to the base interface's action leaves the block out of balance by dM alone, which the check
    divides by its load |(alpha W, W)| = W sqrt(1 + alpha^2) times its size max(b, h):
    dM / (W sqrt(1 + alpha^2) max(b, h))."""
    from limit.solve import verify

    b, h, rho, g = 0.3, 1.0, 2000.0, 9.81
    P = assemble(load_scene(B.single_block(2, b, h, mu=0.8)))
    sol, _, _ = solve_lp(P, "clarabel", fallback=False)
    assert verify.block_equilibrium(P, sol.alpha, sol.x) < 1e-8
    W = rho * b * h * g  # per unit thickness: the 2D scenes' blocks are 1 m deep
    m = np.flatnonzero(P.model.x_is_moment)
    assert m.size == 1
    dM = 0.01 * W * b
    x = sol.x.copy()
    x[m] += dM
    expect = dM / (W * np.hypot(1.0, sol.alpha) * max(b, h))
    assert verify.block_equilibrium(P, sol.alpha, x) == pytest.approx(expect, rel=1e-6)
    assert P.block_size == pytest.approx([max(b, h)])


@pytest.mark.parametrize("name", ["block-tied-2d", "block-water-2d"])
def test_ties_and_pressures_move_with_the_scene(name):
    """A mirrored, a translated and a reordered copy of a scene with a tie or a water pressure keep
    its alpha: the tie's ends and the pressure's face and water level move with the blocks
    (scenes/transform.py). Scaling is left out: capacities and pressures are not scaled."""
    d = json.loads(next(p for p in CATALOG if p.stem == name).read_text())
    a0, *_ = lp_alpha(d)
    for label, v in {"mirrored": transform(d, R=np.diag([-1.0, 1.0])), "translated": transform(d, t=[3.0, 7.0]),
                     "reordered": reorder(d, seed=3)}.items():
        a, *_ = lp_alpha(v)
        assert a == pytest.approx(a0, rel=1e-9), label
