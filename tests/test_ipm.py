"""The structured interior point method (limit.solve.ipm) against Clarabel, and its failure paths.

Clarabel (through cvxpy) is the independent second method: both solve the
same static LP, so their verified alphas must agree; the closed forms are
checked with both solvers in test_lp_closed_form.py.
"""
import json
import math

import numpy as np
import pytest

from limit.errors import SceneError

from limit.solve import ipm, lp as lpmod
from limit.analysis import solve_lp
from limit.model.assemble import Options, assemble
from limit.model.scene import load_scene
from scenes import builders as B
from scenes.catalog import catalog_files
from tests.conftest import catalog_params

CATALOG = catalog_files()


def _both(P):
    ref, _, _ = solve_lp(P, "clarabel", fallback=False)
    got, attempts, _ = solve_lp(P, "ipm", fallback=False)
    return ref, got, attempts


@pytest.mark.parametrize("model", ["paper", "vertex"])
@pytest.mark.parametrize("path", catalog_params(CATALOG))  # a catalog sweep: FAST_CATALOG in the fast subset
def test_same_alpha_as_clarabel_on_catalog(path, model):
    d = json.loads(path.read_text())
    if model == "vertex" and any(j.get("fc") for j in d.get("joints", [])):  # crushing: the paper's model only
        with pytest.raises(SceneError, match="paper's interface model only"):
            assemble(load_scene(d), Options(model=model))
        return
    P = assemble(load_scene(d), Options(model=model))
    ref, got, attempts = _both(P)
    if ref.status == "unbounded":  # the confined block: ipm detects no unboundedness, it fails and falls back
        assert got.status == "failed" and "diverges" in got.reason
        return
    assert got.status == ref.status, (got.reason, attempts)
    assert got.solver == "ipm"
    if ref.status == "optimal":
        assert got.alpha == pytest.approx(ref.alpha, rel=1e-6)
    else:  # the double arch that cannot carry itself: same negative alpha from both
        assert attempts[0]["alpha"] < 0


@pytest.mark.parametrize("dim,n", [pytest.param(2, 1000, marks=pytest.mark.slow), (3, 300)])  # 2D 1,000 blocks: about 3 s
def test_same_alpha_as_clarabel_on_large_walls(dim, n):
    """Walls where the reduced system becomes ill-conditioned near the optimum (iterative refinement at work)."""
    side = int(round(math.sqrt(n)))
    P = assemble(load_scene(B.running_bond_wall(side, side, dim=dim, mu=0.65)))
    ref, got, attempts = _both(P)
    assert ref.status == got.status == "optimal", attempts
    assert got.alpha == pytest.approx(ref.alpha, rel=1e-6)


@pytest.mark.parametrize("correctors", [0, 1, 3])
def test_the_centrality_correctors_leave_alpha_unchanged(correctors):
    """Gondzio's correctors change the path, not the LP: each count gives Clarabel's alpha."""
    P = assemble(load_scene(B.running_bond_wall(12, 12, dim=2, mu=0.65)))
    ref, _, _ = solve_lp(P, "clarabel", fallback=False)
    r = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, correctors=correctors)
    assert r["status"] == "optimal"
    assert r["alpha"] == pytest.approx(ref.alpha, rel=1e-6)


def test_a_structure_built_once_serves_many_solves():
    """Solves of LPs that differ in their yield right-hand side give the same answers from one
    :class:`ipm.Structure` as from their own; one built for other matrices is refused."""
    P = assemble(load_scene(B.running_bond_wall(6, 6, dim=2, mu=0.65)))
    st = ipm.Structure(P.Eh, P.Yh, P.model.x_iface)
    for scale in (0.0, 0.05, 0.2):
        c = np.full(P.Yh.shape[0], scale)
        own = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, c=c)
        shared = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, c=c, structure=st)
        assert own["status"] == shared["status"] == "optimal"
        assert shared["alpha"] == own["alpha"] and np.array_equal(shared["xh"], own["xh"])
    other = assemble(load_scene(B.stack(2, dim=2)))
    with pytest.raises(ValueError, match="other shapes"):
        ipm.solve(other.Eh, other.Yh, other.f0h, other.fLh, other.model.x_iface, structure=st)


def test_no_mechanism_fails_then_clarabel_answers():
    """A live load pressing the block onto its base drives no mechanism: ipm cannot tell, Clarabel can."""
    d = B.single_block(dim=2)
    d["loads"]["live"] = [{"type": "body_force", "direction": [0.0, -1.0]}]
    P = assemble(load_scene(d))
    alone, attempts, _ = solve_lp(P, "ipm", fallback=False)
    assert alone.status == "failed" and alone.alpha is None
    assert alone.reason.startswith("ipm:")
    chained, attempts, _ = solve_lp(P, "ipm", fallback=True)
    assert [a["solver"] for a in attempts][:2] == ["ipm", "clarabel"]
    assert chained.status == "unbounded"


def test_auto_picks_by_size():
    from limit.settings import DEFAULT

    small = assemble(load_scene(B.single_block(dim=2)))
    assert lpmod.resolve("auto", small) == "clarabel"
    big = assemble(load_scene(B.running_bond_wall(32, 32, dim=2)))
    assert big.n_dof >= DEFAULT.lp_ipm_min_dof
    assert lpmod.resolve("auto", big) == "ipm"
    assert lpmod.resolve("ecos", big) == "ecos"
    with pytest.raises(ValueError, match="unknown solver"):
        lpmod.resolve("gurobi", small)


def test_block_inverse_stays_positive_definite():
    """Blocks with condition numbers past 1/eps: a plain inverse may come out indefinite, ours may not."""
    rng = np.random.default_rng(1)
    Q, _ = np.linalg.qr(rng.standard_normal((200, 6, 6)))
    w = 10.0 ** rng.uniform(-12, 12, (200, 6))
    w[:, 0] = 1e-30  # numerically singular
    H = np.einsum("gak,gk,gbk->gab", Q, w, Q)
    Hi = ipm._spd_inverse(H)
    assert np.all(np.isfinite(Hi))
    assert np.allclose(Hi, Hi.transpose(0, 2, 1))
    assert np.linalg.eigvalsh(Hi).min() > 0
    # and on well-conditioned blocks it is the inverse
    Hw = np.einsum("gak,gk,gbk->gab", Q, 1.0 + rng.random((200, 6)), Q)
    assert np.allclose(ipm._spd_inverse(Hw) @ Hw, np.eye(6), atol=1e-9)


@pytest.mark.parametrize("dim", [2, 3])
def test_interface_blocks_are_the_inverses_of_their_yield_rows(dim):
    """_Blocks.inverse(d, q) against numpy, interface by interface: the inverse of
    ``Y_i.T diag(d_i) Y_i + diag(q_i)``, Y_i the yield rows of interface i on its own actions
    (a wall's Yh, random face weights d and proximal weights q)."""
    P = assemble(load_scene(B.running_bond_wall(4, 4, dim=dim, mu=0.7)))
    rng = np.random.default_rng(3)
    d = 10.0 ** rng.uniform(-2, 2, P.Yh.shape[0])
    q = rng.uniform(0.0, 1.0, P.model.n_x)
    blocks = ipm._Blocks(P.Yh, P.model.x_iface)
    Hinv = blocks.matrix(blocks.inverse(d, q)).toarray()
    Y = P.Yh.toarray()
    for i in np.unique(P.model.x_iface):
        cols = np.flatnonzero(P.model.x_iface == i)
        rows = np.flatnonzero(np.abs(Y[:, cols]).sum(axis=1) > 0)
        H = Y[np.ix_(rows, cols)].T @ np.diag(d[rows]) @ Y[np.ix_(rows, cols)] + np.diag(q[cols])
        assert np.allclose(Hinv[np.ix_(cols, cols)], np.linalg.inv(H), rtol=1e-9, atol=1e-12)
    assert np.count_nonzero(Hinv) == sum(np.sum(P.model.x_iface == i) ** 2 for i in np.unique(P.model.x_iface))


def test_unsorted_actions_are_rejected():
    P = assemble(load_scene(B.stack(2, dim=2)))
    with pytest.raises(ValueError, match="interface by interface"):
        ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface[::-1])


def test_reduced_system_shift():
    """N = Eh Hinv Eh.T: a singular N factors once shifted; an indefinite one is refused."""
    P = assemble(load_scene(B.stack(2, dim=2)))
    blocks = ipm._Blocks(P.Yh.tocsr(), P.model.x_iface)
    red = ipm._Reduced(P.Eh.tocsr(), blocks)
    zero = [np.zeros((xidx.shape[0], xidx.shape[1], xidx.shape[1])) for *_, xidx in blocks.classes]
    red.factor(zero)  # N = 0: only the shift makes it definite
    rhs = np.arange(1.0, P.n_dof + 1)
    assert np.all(np.isfinite(red.solve(rhs)))
    with pytest.raises(ArithmeticError):
        red.factor([-np.broadcast_to(np.eye(h.shape[1]), h.shape) for h in zero])


@pytest.mark.parametrize("dim", [2, 3])
def test_reduced_system_is_the_sparse_product(dim):
    """N summed interface by interface equals scipy's Eh Hinv Eh.T (lower triangle), with Hinv
    the block-diagonal matrix of the same random positive definite blocks."""
    import scipy.sparse as sp

    P = assemble(load_scene(B.running_bond_wall(4, 5, dim=dim)))
    blocks = ipm._Blocks(P.Yh.tocsr(), P.model.x_iface)
    red = ipm._Reduced(P.Eh.tocsr(), blocks)
    rng = np.random.default_rng(3)
    hinv = []
    for *_, xidx in blocks.classes:
        A = rng.standard_normal((xidx.shape[0], xidx.shape[1], xidx.shape[1]))
        hinv.append(A @ A.transpose(0, 2, 1) + np.eye(xidx.shape[1]))
    Hinv = blocks.matrix(hinv)
    dense = np.zeros((blocks.n_x, blocks.n_x))
    for (*_, xidx), h in zip(blocks.classes, hinv):
        for g in range(xidx.shape[0]):
            dense[np.ix_(xidx[g], xidx[g])] = h[g]
    assert np.array_equal(Hinv.toarray(), dense)
    N = sp.tril(P.Eh @ sp.csr_matrix(dense) @ P.Eh.T).toarray()
    got = np.zeros_like(N)
    M = red._M
    got[np.array(M.I).ravel(), np.array(M.J).ravel()] = red.assemble(hinv)
    assert np.allclose(got, N, rtol=1e-12, atol=1e-12 * np.abs(N).max())


def test_cli_offers_every_solver():
    """The CLI lists the solver names without importing cvxpy; the list must follow limit.solve.lp."""
    from limit import cli
    assert sorted(cli.LP_SOLVERS) == sorted(lpmod.SOLVERS) and set(lpmod.CVXPY_SOLVERS) | {"ipm", "auto"} == set(lpmod.SOLVERS)


def test_warm_start_reaches_the_cold_answer_of_a_changed_lp():
    """The iterative LP of step 2 changes only the yield right-hand side c between LPs. A solve
    warm-started from the first LP's point must reach the optimum of the second LP that HiGHS
    finds on its own (a second method; the problem built by limit.solve.lpsub): the friction
    capacities of a 2D wall of 100 blocks, moved from the LP's N to 0.7 N."""
    import scipy.sparse as sp

    from limit.solve import iterative_lp, lpsub

    P = assemble(load_scene(B.running_bond_wall(10, 10, dim=2, mu=0.9)))
    sol, _, _ = solve_lp(P, "clarabel", fallback=False)
    fr, Yc, ncol, ncoef = iterative_lp.friction_rows(P)
    nstar = (sol.x / P.Dx)[ncol]

    def rhs(scale):
        c = np.zeros(Yc.shape[0])
        c[fr] = -ncoef * np.maximum(scale * nstar, 1e-8 * nstar.max())
        return c

    first = ipm.solve(P.Eh, Yc, P.f0h, P.fLh, P.model.x_iface, c=rhs(1.0))
    warm = ipm.solve(P.Eh, Yc, P.f0h, P.fLh, P.model.x_iface, c=rhs(0.7), warm=first)
    nx = P.model.n_x
    ref = lpsub.solve(np.r_[-1.0, np.zeros(nx)], sp.hstack([sp.csr_matrix(P.fLh.reshape(-1, 1)), P.Eh]).tocsr(),
                      -P.f0h, sp.hstack([sp.csr_matrix((Yc.shape[0], 1)), Yc]).tocsr(), rhs(0.7),
                      np.full(1 + nx, -np.inf), np.full(1 + nx, np.inf), "highs")
    assert first["status"] == warm["status"] == "optimal" and ref.ok
    assert warm["alpha"] == pytest.approx(ref.z[0], rel=1e-7)
    assert abs(warm["alpha"] - first["alpha"]) > 1e-3  # the second LP is a different one


@pytest.mark.parametrize("dim", [2, 3])
def test_proximal_qp_against_clarabel(dim):
    """The proximal form ``min -alpha + 1/2 sum q (x - x_ref)^2`` (limit.solve.ipm.solve's q,
    x_ref) against the same convex QP in cvxpy/Clarabel, on a small running-bond wall, with the
    normal forces pulled toward zero: the same alpha and actions. And with x_ref an optimum of the LP itself the term vanishes there
    and is >= 0 elsewhere, so the QP's alpha is the LP's."""
    import cvxpy as cp

    P = assemble(load_scene(B.running_bond_wall(3, 3, dim=dim, mu=0.7)))
    lp = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface)
    assert lp["status"] == "optimal"
    n_x = P.Yh.shape[1]
    q = np.where(P.model.normal_col, 2.0, 0.0)
    x_ref = np.zeros(n_x)  # pulls every normal force to zero, which equilibrium forbids: alpha drops
    got = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, q=q, x_ref=x_ref)
    x, a = cp.Variable(n_x), cp.Variable()
    prob = cp.Problem(cp.Minimize(-a + 0.5 * cp.sum(cp.multiply(q, cp.square(x - x_ref)))),
                      [P.Eh @ x + P.fLh * a == -P.f0h, P.Yh @ x <= 0])
    prob.solve(solver="CLARABEL")
    assert got["status"] == "optimal" and prob.status == "optimal"
    assert got["alpha"] == pytest.approx(a.value, abs=1e-6)
    assert np.max(np.abs(got["xh"] - x.value) * np.sqrt(q)) < 1e-4
    assert got["alpha"] < lp["alpha"] - 1e-6  # the pull toward x_ref costs alpha here
    same = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, q=q, x_ref=lp["xh"])
    assert same["status"] == "optimal" and same["alpha"] == pytest.approx(lp["alpha"], abs=1e-7)


def test_an_infeasible_lp_stops_once_mu_diverges():
    """A block on its base whose yield rows are shifted out of reach (c = -1 on every face: each
    face at least 1, scaled, inside its yield value, a margin that its weight's normal force
    cannot give): no feasible point. With mu_diverged the method stops within a few iterations and says so;
    without it, it runs to max_iter. Clarabel and HiGHS (second methods) prove it infeasible, which
    their results say as ``no_point`` (what the snap of step2_large reads)."""
    from limit.solve import lpsub
    import scipy.sparse as sp

    P = assemble(load_scene(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)))
    c = -np.ones(P.Yh.shape[0])
    args = (P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface)
    fast = ipm.solve(*args, c=c, max_iter=100, mu_diverged=1e6)
    assert fast["status"] == "failed" and "no feasible point" in fast["reason"] and fast["iterations"] < 40
    assert fast["diverged"]
    slow = ipm.solve(*args, c=c, max_iter=100)
    assert slow["status"] == "failed" and slow["iterations"] > fast["iterations"] and not slow["diverged"]
    nx = P.model.n_x
    A = sp.hstack([sp.csr_matrix(P.fLh.reshape(-1, 1)), P.Eh]).tocsr()
    for backend in ("clarabel", "highs"):
        ref = lpsub.solve(np.r_[-1.0, np.zeros(nx)], A, -P.f0h, sp.hstack([sp.csr_matrix((len(c), 1)), P.Yh]).tocsr(),
                          c, np.full(nx + 1, -np.inf), np.full(nx + 1, np.inf), backend)
        assert not ref.ok and ref.no_point and "nfeasible" in ref.status, backend
    feasible = ipm.solve(*args, max_iter=100, mu_diverged=1e6)  # c = 0: the block's own LP, alpha = b/h
    assert feasible["status"] == "optimal" and not feasible["diverged"]


def test_almost_returns_the_best_iterate_of_an_unfinished_solve():
    """Stopped after 4 iterations (far from tol): without ``almost`` the solve fails; with an
    ``almost`` above its residual it returns status "almost" and the iterate of lowest residual,
    which is then no worse than the last one (Clarabel's alpha is the reference for both)."""
    P = assemble(load_scene(B.running_bond_wall(3, 3, dim=2, mu=0.9)))
    args = (P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface)
    ref, _, _ = solve_lp(P, "clarabel", fallback=False)
    bare = ipm.solve(*args, max_iter=4)
    kept = ipm.solve(*args, max_iter=4, almost=10.0)
    assert bare["status"] == "failed" and kept["status"] == "almost" and "best iterate" in kept["reason"]
    assert abs(kept["alpha"] - ref.alpha) <= abs(bare["alpha"] - ref.alpha) + 1e-12
    assert ipm.solve(*args, max_iter=4, almost=1e-12)["status"] == "failed"  # residual above almost


def test_a_step1_lp_that_stalls_short_of_its_tolerance_is_checked_not_lost():
    """lp.IPM_ALMOST: asked for a tolerance no iterate reaches (1e-16; rounding stops the residuals
    near 1e-12), the method stalls; its best iterate comes back "inaccurate", passes the
    independent check of step 1 (limit.solve.verify, 1e-6) and gives Clarabel's alpha. With no
    ``almost`` it is a failure, as every stall was before."""
    P = assemble(load_scene(B.running_bond_wall(4, 4, dim=3, L=0.4, H=0.3, mu=0.9)))
    ref, _, _ = solve_lp(P, "clarabel", fallback=False)
    raw = lpmod.static_lp(P, "ipm", overrides={"tol": 1e-16})
    assert raw.status == "inaccurate" and raw.cvxpy_status == "ipm almost", raw.reason
    got, _, _ = solve_lp(P, "ipm", fallback=False)
    assert got.status == "optimal"
    from limit.solve import verify
    ok, _, why = verify.check_lp(P, raw)
    assert ok, why
    assert raw.alpha == pytest.approx(ref.alpha, rel=1e-7) and got.alpha == pytest.approx(ref.alpha, rel=1e-7)
    strict = lpmod.static_lp(P, "ipm", overrides={"tol": 1e-16, "almost": None})
    assert strict.status == "failed" and strict.alpha is None
