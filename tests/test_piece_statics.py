"""The statics half of the snap's piece LP on the structured interior point method
(limit/solve/piece_statics.py), against the same LP with the flowing faces as equalities solved
by HiGHS's simplex (the second method), and against closed forms.

Closed forms (a block b x h on a fixed base, self weight W dead, a horizontal body force
alpha W live):
  * with the base's sliding face flowing, V = mu N with N = W and V = alpha W: alpha = mu;
  * with the toe's rocking face flowing, the resultant sits at the toe: alpha W h/2 = W b/2,
    alpha = b/h.
"""
import numpy as np
import pytest
import scipy.sparse as sp

from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from limit.solve import lpsub, nlp, piece_statics, step2_large
from limit.solve.nlp_problem import build
from scenes import builders as B


def _solved(data):
    P = assemble(load_scene(data))
    sol, _, _ = solve_lp(P)
    return P, sol


def _simplex_statics(P, flows):
    """min alpha s.t. Eh x + fLh alpha = -f0h, Yh[flowing] x = 0, Yh[other] x <= 0, alpha >= 0 (HiGHS)."""
    act, hold = np.flatnonzero(flows), np.flatnonzero(~flows)
    Yh = sp.csr_matrix(P.Yh)
    nx = P.model.n_x
    Aeq = sp.vstack([sp.hstack([sp.csr_matrix(P.fLh.reshape(-1, 1)), P.Eh]),
                     sp.hstack([sp.csr_matrix((act.size, 1)), Yh[act]])]).tocsr()
    Aub = sp.hstack([sp.csr_matrix((hold.size, 1)), Yh[hold]]).tocsr()
    c = np.zeros(1 + nx)
    c[0] = 1.0
    lo = np.full(1 + nx, -np.inf)
    lo[0] = 0.0
    res = lpsub.solve(c, Aeq, np.concatenate([-P.f0h, np.zeros(act.size)]), Aub, np.zeros(hold.size), lo,
                      np.full(1 + nx, np.inf), "highs")
    return res.z[0] if res.ok else None


def _lp_flows(P, sol):
    lam = np.asarray(sol.lam)
    return lam > 1e-7 * lam.max()


@pytest.mark.parametrize("dim", [2, 3])
def test_null_spaces_are_orthonormal_bases_interface_by_interface(dim):
    """Z spans exactly {x : Yh[flowing] x = 0}: Yh[flowing] Z = 0, Z.T Z = I, and each interface
    keeps k - rank(its flowing rows) columns (numpy's matrix_rank, per interface), its own."""
    P, _ = _solved(B.running_bond_wall(4, 3, dim=dim, mu=0.7))
    Yh, xg = sp.csr_matrix(P.Yh), P.model.x_iface
    rng = np.random.default_rng(1)
    for frac in (0.0, 0.1, 0.4, 1.0):
        act = np.flatnonzero(rng.random(Yh.shape[0]) < frac)
        Z, ui = piece_statics.null_spaces(Yh, xg, act)
        if act.size and Z.shape[1]:
            assert abs(Yh[act] @ Z).max() < 1e-12
        assert np.allclose((Z.T @ Z).toarray(), np.eye(Z.shape[1]), atol=1e-12)
        coo = Z.tocoo()
        assert np.all(xg[coo.row] == ui[coo.col])
        face_if = xg[Yh.indices[Yh.indptr[:-1]]]
        for g in np.unique(xg):
            cols = np.flatnonzero(xg == g)
            rows = act[face_if[act] == g]
            rank = np.linalg.matrix_rank(Yh[rows][:, cols].toarray()) if rows.size else 0
            assert (ui == g).sum() == cols.size - rank


@pytest.mark.parametrize("dim", [2, 3])
def test_sliding_and_rocking_blocks_give_their_closed_forms(dim):
    kw = {"t": 0.5} if dim == 3 else {}
    for b, h, mu, alpha in ((1.0, 0.5, 0.4, 0.4), (0.3, 1.0, 0.6, 0.3)):
        P, sol = _solved(B.single_block(dim=dim, b=b, h=h, mu=mu, **kw))
        st = piece_statics.solve(P, _lp_flows(P, sol))
        assert st.alpha == pytest.approx(alpha, abs=1e-7), st.note


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # 3D: about 4 s
def test_the_same_minimum_as_the_simplex_or_no_answer_where_it_has_none(dim):
    """Flowing sets of a verified step-2 point (both snap rules), of the LP's mechanism and 12
    random ones: where HiGHS finds the minimum the interior point gives it to 1e-7; where HiGHS
    finds no point (infeasible), no alpha; where the minimum sits on the bound alpha >= 0 (the
    interior point has no bound on alpha), no alpha and the reason (the snap then asks Clarabel)."""
    P, sol = _solved(B.running_bond_wall(4, 4, dim=dim, L=0.4, H=0.3, mu=0.9))
    N = build(P)
    out = step2_large.solve(P, sol, workers=1)
    assert out.ok
    sets = [nlp.flowing_faces(N, out.z, rule) for rule in ("support", "ratio")] + [_lp_flows(P, sol)]
    rng = np.random.default_rng(0)
    sets += [rng.random(P.model.n_faces) < frac for frac in (0.02, 0.05, 0.1, 0.2) for _ in range(3)]
    answered = unanswered = 0
    for flows in sets:
        ref = _simplex_statics(P, flows)
        st = piece_statics.solve(P, flows)
        if ref is None:
            assert st.alpha is None, st.note
            unanswered += 1
        elif ref < 1e-9 and st.alpha is None:
            assert "below 0" in st.note and not st.diverged
        else:
            assert st.alpha == pytest.approx(ref, abs=1e-7), st.note
            assert not st.diverged
            answered += 1
    assert answered >= 3 and unanswered >= 1  # both branches were exercised


def test_the_snap_with_it_passes_the_independent_check():
    """The whole snap with backend "ipm" (kinematics on rigid clusters, statics here) from a
    verified point's flowing faces: a point that passes nlp.check, at the verified alpha."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    N = build(P)
    out = step2_large.solve(P, sol, workers=1)
    zp, why, infeasible, diverged = step2_large.snap(N, out.z, "support", "ipm")
    assert zp is not None and not infeasible and not diverged, why
    ok, _, reason = nlp.check(N, zp, sol.alpha)
    assert ok, reason
    assert zp[N.ia] == pytest.approx(out.alpha, abs=1e-7)
