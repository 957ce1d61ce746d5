"""The statics half of the snap's piece LP on the structured interior point method.

With the flowing faces fixed, the statics of the piece LP (:func:`limit.solve.step2_large.snap`)
is (scaled units, :mod:`limit.solve.lp`)::

    minimise alpha  s.t.  Eh x + fLh alpha = -f0h,   Yh_act x = 0,   Yh_hold x <= 0

An interior point method needs ``Yh x <= c`` with room inside, so the flowing faces' equalities
are eliminated interface by interface: each interface's actions are written
``x_i = Z_i u_i``, Z_i an orthonormal basis of the null space of its flowing faces' rows (an SVD
of a few rows of 3 or 6 columns; Z_i = I where no face flows, no column where the flowing faces
pin every action). The reduced LP keeps one block per interface (of 0 to 6 actions), which is
what :func:`limit.solve.ipm.solve` factors, and ``min alpha`` is its ``max alpha'`` with the live
load's column negated (alpha' = -alpha). Faces that do not flow and whose row vanishes on the
reduced actions (parallel to a flowing one) hold with equality and are dropped.

At a 3D wall of 3,024 blocks Clarabel took 16-26 s per statics LP, a quarter of a start's
time; this solves the same LP on the structure of
the iterative LP's LPs. No infeasibility detection: a failure (the method not converging) is
reported, and the caller asks a general solver.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from limit.solve.status import IpmStatus

#: a flowing face's row counts towards the null space above this x the interface's largest singular value
RANK_RTOL = 1e-10
#: a face that does not flow is dropped when its reduced row's norm is at most this x its own
DROP_RTOL = 1e-10
#: interior point iterations of the statics LP (step 1's LPs take 40-90)
MAX_ITER = 120
#: ... which stops once its mean complementarity has grown this much (ipm.solve's ``mu_diverged``):
#: a piece whose statics has no point (the flowing faces guessed wrong) costs a few iterations
MU_DIVERGED = 1e6


def null_spaces(Yh: sp.csr_matrix, x_iface: np.ndarray, act: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """(Z (n_x, n_u), interface of each reduced action (n_u,)): block diagonal, Z_i an orthonormal
    basis of {x_i : Yh[act faces of i] x_i = 0} (identity for an interface without flowing faces).
    ``act``: indices of the flowing faces (rows of Yh). One stacked SVD per interface size."""
    Yh = sp.csr_matrix(Yh)
    x_iface = np.asarray(x_iface)
    act = np.asarray(act, dtype=np.int64)
    n_if = int(x_iface.max(initial=-1)) + 1
    first = np.searchsorted(x_iface, np.arange(n_if))
    size = np.searchsorted(x_iface, np.arange(n_if), side="right") - first
    if np.any(np.diff(Yh.indptr)[act] == 0):
        raise ValueError("a flowing face has an empty yield row")
    A = Yh[act].tocoo()
    g_of_face = x_iface[A.col[np.r_[0, np.flatnonzero(np.diff(A.row)) + 1]]] if A.nnz else np.empty(0, int)
    order = np.argsort(g_of_face, kind="stable")  # act faces interface by interface
    gs = g_of_face[order]
    slot = np.arange(gs.size) - np.searchsorted(gs, gs)  # a face's place among its interface's
    touched = np.unique(gs)
    width = size.copy()
    bases = []  # (interfaces, their bases (n, k, r) zero-padded, r per interface)
    for k in np.unique(size[touched]):
        tg = touched[size[touched] == k]
        sel = np.isin(gs, tg)
        idx = np.searchsorted(tg, gs[sel])
        M = np.zeros((tg.size, int(slot[sel].max(initial=0)) + 1, k))
        face_rows = order[sel]  # rows of A (= positions in act) of these faces
        in_sel = np.full(order.size, -1)
        in_sel[face_rows] = np.arange(face_rows.size)
        m = in_sel[A.row] >= 0
        j = in_sel[A.row[m]]
        M[idx[j], slot[sel][j], A.col[m] - first[gs[sel][j]]] = A.data[m]
        _, sv, Vt = np.linalg.svd(M, full_matrices=True)
        sv_full = np.zeros((tg.size, k))
        sv_full[:, :sv.shape[1]] = sv
        tol = RANK_RTOL * np.maximum(sv_full.max(axis=1), 1e-300)
        rank = (sv_full > tol[:, None]).sum(axis=1)
        width[tg] = k - rank
        bases.append((tg, Vt, rank))
    col0 = np.concatenate([[0], np.cumsum(width)[:-1]])
    plain = np.ones(n_if, dtype=bool)
    plain[touched] = False
    pg = np.flatnonzero(plain)
    kk = size[pg]
    off = np.arange(kk.sum()) - np.repeat(np.cumsum(kk) - kk, kk)
    rows, cols, vals = [np.repeat(first[pg], kk) + off], [np.repeat(col0[pg], kk) + off], [np.ones(off.size)]
    for tg, Vt, rank in bases:  # rows rank..k-1 of an interface's Vt span its null space
        k = Vt.shape[1]
        gi, r = np.nonzero(np.arange(k)[None, :] >= rank[:, None])
        rows.append((first[tg[gi]][:, None] + np.arange(k)[None, :]).ravel())
        cols.append(np.repeat(col0[tg[gi]] + r - rank[gi], k))
        vals.append(Vt[gi, r, :].ravel())
    n_u = int(width.sum())
    Z = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(Yh.shape[1], n_u))
    return Z, np.repeat(np.arange(n_if), width)


class Statics(NamedTuple):
    """The outcome of :func:`solve`: ``alpha`` and ``xh`` (n_x,), both None on failure; ``note``
    (how it was solved, or why it failed); ``diverged``: the interior point method stopped on
    ``mu_diverged`` (:data:`MU_DIVERGED`), which an infeasible piece does; no proof."""
    alpha: float | None
    xh: np.ndarray | None
    note: str
    diverged: bool = False


def solve(P, flows: np.ndarray, tol: float = 1e-9, max_iter: int = MAX_ITER) -> Statics:
    """The statics piece LP for the flowing faces ``flows`` (bool, (n_faces,)), as a
    :class:`Statics`: alpha None when the interior point method does not converge (an
    infeasible or unbounded piece among them) or its minimum is below 0."""
    from limit.solve import ipm

    Yh = sp.csr_matrix(P.Yh)
    act = np.flatnonzero(flows)
    hold = np.flatnonzero(~flows)
    Z, u_iface = null_spaces(Yh, P.model.x_iface, act)
    Yhold = Yh[hold]
    Yr = (Yhold @ Z).tocsr()
    own = np.sqrt(np.asarray(Yhold.multiply(Yhold).sum(axis=1)).ravel())
    red = np.sqrt(np.asarray(Yr.multiply(Yr).sum(axis=1)).ravel())
    keep = red > DROP_RTOL * np.maximum(own, 1e-300)
    Yr = Yr[np.flatnonzero(keep)]
    if Yr.shape[0] == 0 or Z.shape[1] == 0:
        return Statics(None, None, "interior point: the flowing faces leave no face to hold")
    Er = (sp.csr_matrix(P.Eh) @ Z).tocsr()
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # a diverging piece is reported below
        r = ipm.solve(Er, Yr, P.f0h, -np.asarray(P.fLh, float), u_iface, tol=tol, max_iter=max_iter,
                      mu_diverged=MU_DIVERGED)
    if r["status"] != IpmStatus.OPTIMAL:
        return Statics(None, None, f"interior point: {r['reason']}", bool(r["diverged"]))
    alpha = -float(r["alpha"])
    if alpha < -tol:
        return Statics(None, None, f"interior point: the minimum alpha {alpha:.3g} is below 0")
    return Statics(max(alpha, 0.0), Z @ r["xh"], f"interior point, {r['iterations']} iterations")
