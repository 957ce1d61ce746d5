"""The snap's kinematics on rigid clusters (limit/solve/rigid_clusters.py) against the same
LP on every block dof (the second method), and against rigid-body motion.

A rigid motion of blocks with velocities at their centroids c_i (2D: [ux, uy, rz]) has one
rotation rate w and u_i - u_j = w x (c_i - c_j): ux_i - ux_j = -w (y_i - y_j),
uy_i - uy_j = w (x_i - x_j). A stack that overturns as one about its base's toe is such a motion.
The flow residuals are held to 1e-7 (Clarabel's interior point stops at 1e-9 of its scaled
problem; the route's independent check allows 1e-6, limit/solve/verify.py).
"""
import numpy as np
import pytest
import scipy.sparse as sp

from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from limit.solve import lpsub, nlp, rigid_clusters, step2_large
from limit.solve.nlp_problem import build
from scenes import builders as B


def _full_kinematics(P, N, flows):
    """The flow LP on every block dof (what the snap solved before): feasible or not."""
    act = np.flatnonzero(flows)
    nv = P.n_dof
    Keq = sp.vstack([sp.hstack([P.Eh.T, -N.Gh[:, act]]),
                     sp.hstack([sp.csr_matrix(P.fLh.reshape(1, -1)), sp.csr_matrix((1, act.size))])]).tocsr()
    keq = np.concatenate([np.zeros(P.model.n_x), [1.0]])
    n = nv + act.size
    lo = np.concatenate([np.full(nv, -np.inf), np.zeros(act.size)])
    return lpsub.solve(np.zeros(n), Keq, keq, sp.csr_matrix((0, n)), np.zeros(0), lo, np.full(n, np.inf), "highs").ok


def _flow_residual(P, N, flows, vh, lam):
    lamh = np.zeros(P.model.n_faces)
    lamh[flows] = lam
    return float(np.abs(P.Eh.T @ vh - N.Gh @ lamh).max()), float(P.fLh @ vh)


def _lp_flows(P, sol):
    lam = np.asarray(sol.lam)
    return lam > 1e-7 * lam.max()


def test_a_stack_overturning_as_one_is_one_cluster_moving_rigidly():
    P = assemble(load_scene(B.stack(3, dim=2, b=0.3, h=0.5, mu=0.8)))
    sol, _, _ = solve_lp(P)
    N = build(P)
    flows = _lp_flows(P, sol)
    T, explicit = rigid_clusters.clusters(P, flows)
    assert T.shape[1] == 3  # the three blocks are one cluster: three unknowns
    vh, lam, _, _ = rigid_clusters.kinematics(P, N.Gh, flows)
    res, fl = _flow_residual(P, N, flows, vh, lam)
    assert res < 1e-9 and fl == pytest.approx(1.0, abs=1e-9) and (lam >= 0).all()
    _, _, u, _ = N.unscale(N.join(0.0, np.zeros(P.model.n_x), vh, np.zeros(P.model.n_faces)))
    u = u.reshape(3, 3)
    c = np.array([P.scene.blocks[i].centroid for i in P.scene.free])
    w = u[0, 2]
    assert np.allclose(u[:, 2], w, atol=1e-9 * abs(w))
    assert np.allclose(u[:, 0] - u[0, 0], -w * (c[:, 1] - c[0, 1]), atol=1e-9 * abs(w))
    assert np.allclose(u[:, 1] - u[0, 1], w * (c[:, 0] - c[0, 0]), atol=1e-9 * abs(w))


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # 3D: about 2 s
def test_feasible_exactly_where_the_flow_lp_on_every_dof_is(dim):
    """Flowing sets: those of a verified frictional collapse state (step 2), of the LP mechanism
    (dilatant: no mechanism with the non-associative flow), every face, and random ones. Where
    there is none, the backend proves it (``no_point``)."""
    P = assemble(load_scene(B.running_bond_wall(4, 4, dim=dim, L=0.4, H=0.3, mu=0.9)))
    sol, _, _ = solve_lp(P)
    N = build(P)
    rng = np.random.default_rng(7)
    out = step2_large.solve(P, sol, workers=1)
    assert out.ok
    sets = [nlp.flowing_faces(N, out.z, "ratio"), _lp_flows(P, sol), np.ones(P.model.n_faces, bool)]
    sets += [rng.random(P.model.n_faces) < p for p in (0.05, 0.2, 0.5, 0.8) for _ in range(3)]
    agree = []
    for flows in sets:
        vh, lam, status, no_point = rigid_clusters.kinematics(P, N.Gh, flows)
        full = _full_kinematics(P, N, flows)
        agree.append((vh is not None) == full)
        assert no_point == (vh is None), status  # no mechanism is proved so (the snap then asks no other backend)
        if vh is not None:
            res, fl = _flow_residual(P, N, flows, vh, lam)
            assert res < 1e-7 and fl == pytest.approx(1.0, abs=1e-7) and (lam >= 0).all()
    assert all(agree)
    assert rigid_clusters.kinematics(P, N.Gh, sets[0])[0] is not None


def test_a_block_with_a_blocked_dof_keeps_its_own_unknowns():
    """The top block of a stack on a roller (x blocked): it is not merged, and the answer still
    satisfies the flow on every dof, as the LP on every dof does."""
    data = B.stack(3, dim=2, b=0.3, h=0.5, mu=0.8)
    data["blocks"][-1]["blocked"] = ["x"]
    P = assemble(load_scene(data))
    assert P.n_dof == 8
    sol, _, _ = solve_lp(P)
    N = build(P)
    for flows in (_lp_flows(P, sol), np.ones(P.model.n_faces, bool)):
        vh, lam, _, _ = rigid_clusters.kinematics(P, N.Gh, flows)
        assert (vh is not None) == _full_kinematics(P, N, flows)
        if vh is not None:
            res, fl = _flow_residual(P, N, flows, vh, lam)
            assert res < 1e-7 and fl == pytest.approx(1.0, abs=1e-7)


def test_two_blocks_sharing_two_interfaces_are_one_cluster():
    """A compound L block and a block C laid in its corner share two interfaces (C on the foot and
    against the leg, tests/test_compound.py). With only the base joint's faces flowing, L and C
    are one cluster (3 unknowns) whose motion satisfies the flow rule on every interface, the two
    tied ones included (residual as in the tests above); with none flowing nothing moves."""
    from tests.test_compound import l_block_2d

    d = l_block_2d()
    d["blocks"].append({"id": "C", "box": {"center": [0.6, 0.4], "size": [0.8, 0.4]}})
    P = assemble(load_scene(d))
    N = build(P)
    iface = np.asarray(P.model.iface)
    base_joint = [k for k, (a, b) in enumerate(zip(P.I.a, P.I.b)) if a == 0]
    flows = np.isin(iface, base_joint)
    T, _ = rigid_clusters.clusters(P, flows)
    assert T.shape[1] == 3
    vh, lam, _, _ = rigid_clusters.kinematics(P, N.Gh, flows)
    assert vh is not None
    res, fl = _flow_residual(P, N, flows, vh, lam)
    assert res < 1e-7 and fl == pytest.approx(1.0, abs=1e-7)
    assert rigid_clusters.clusters(P, np.zeros(P.model.n_faces, bool))[0].shape[1] == 0


@pytest.mark.parametrize("cheap", ["slide", "rock"])
def test_the_least_slack_mechanism_flows_where_the_weights_are_zero(cheap):
    """rigid_clusters.least_slack_flow: min w . lam over the mechanisms (fL . u = 1). One block,
    b = 0.3 by h = 1.0, on a fixed base, pushed along +x. Weights 0 on the sliding faces and 1 on
    the rocking ones: the free mechanism is the pure slide (u = [1/W, 0, 0] up to the
    normalisation; ux > 0, uy = rz = 0) and no rocking face flows. Weights the other way round:
    the block rocks about its right toe p = (b, 0) with rate w < 0 (clockwise): its centroid
    c = (b/2, h/2) moves u = w x (c - p), so ux = -w h/2 and uy = -w b/2. Lifting off the base
    (ux = 0, uy > 0: both rocking faces open) is free too, as the normalisation asks for the
    live load's work only: every optimum has rz = -ux / (h/2), uy / ux >= b / h, and no sliding
    face flows."""
    from limit.model.yield_domain import ROCK, SLIDE

    P = assemble(load_scene(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)))
    N = build(P)
    kind = P.model.kind
    w = np.where(kind == (ROCK if cheap == "slide" else SLIDE), 1.0, 0.0)
    kin = rigid_clusters.least_slack_flow(P, N.Gh, w)
    assert kin.vh is not None
    _, _, u, lam = N.unscale(N.join(0.0, np.zeros(P.model.n_x), kin.vh, kin.lam))
    lam = np.maximum(lam, 0.0)
    flowing = lam > 1e-7 * lam.max()
    assert flowing.any() and float(w @ kin.lam) < 1e-8
    if cheap == "slide":
        assert set(kind[flowing]) == {SLIDE}
        assert u[0] > 0 and abs(u[1]) < 1e-7 * u[0] and abs(u[2]) < 1e-7 * u[0]
    else:
        assert set(kind[flowing]) == {ROCK}
        assert u[0] > 0 and u[2] == pytest.approx(-u[0] / 0.5, rel=1e-6) and u[1] / u[0] >= 0.3 * (1 - 1e-6)
