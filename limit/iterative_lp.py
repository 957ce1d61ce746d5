"""The iterative LP of Gilbert, Casapulla & Ahmed (Computers & Structures 84, 2006, 873-887).

An independent route to the frictional collapse factor: the Coulomb bound of
every sliding (and twisting) face, ``|V| <= mu N``, is replaced by a fixed
shear capacity ``|V| <= mu N*`` with N* the normal force of the previous
iteration, which makes the LP associative *without* dilatancy (the face no
longer involves N). After each LP, ``N* <- N* + omega (N - N*)`` (relaxation
omega), until the normal forces settle. The rocking faces are unchanged.
Started from the normal forces of the associative LP.
"""
from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp

from . import lpsub
from .yield_domain import SLIDE, TWIST


def _normal_columns(P, rows):
    """For each yield row, the column of the normal force it involves."""
    Y = P.Yh[rows].tocoo()
    is_n = P.model.normal_col[Y.col]
    col = np.full(len(rows), -1)
    col[Y.row[is_n]] = Y.col[is_n]
    coef = np.zeros(len(rows))
    coef[Y.row[is_n]] = Y.data[is_n]
    return col, coef


def solve(P, lp_sol, omega: float = 0.5, tol: float = 1e-8, max_iter: int = 300, backend: str = "highs") -> dict:
    """{"status", "alpha", "iterations", "history", "time_s"} of the iterative LP."""
    t0 = time.perf_counter()
    kind = P.model.kind
    fr = np.flatnonzero((kind == SLIDE) | (kind == TWIST))
    ncol, ncoef = _normal_columns(P, fr)
    # Yield rows with the normal-force term of the friction faces removed (moved to the right-hand side).
    Yc = P.Yh.tolil(copy=True)
    for j, cidx in zip(fr, ncol):
        if cidx >= 0:
            Yc[j, cidx] = 0.0
    Yc = Yc.tocsr()
    nx = P.model.n_x
    n = 1 + nx
    Aeq = sp.hstack([sp.csr_matrix(P.fLh.reshape(-1, 1)), P.Eh]).tocsr()
    Aub = sp.hstack([sp.csr_matrix((Yc.shape[0], 1)), Yc]).tocsr()
    c = np.zeros(n)
    c[0] = -1.0
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    xh = lp_sol.x / P.Dx
    nstar = xh[ncol]
    history = []
    alpha = None
    for it in range(1, max_iter + 1):
        b = np.zeros(Yc.shape[0])
        b[fr] = -ncoef * np.maximum(nstar, 0.0)
        res = lpsub.solve(c, Aeq, -P.f0h, Aub, b, lo, hi, backend)
        if not res.ok:
            return {"status": "failed", "alpha": None, "iterations": it, "history": history,
                    "time_s": time.perf_counter() - t0, "reason": f"LP {it}: {res.status}"}
        alpha = float(res.z[0])
        nnew = res.z[1:][ncol]
        history.append(alpha)
        change = float(np.max(np.abs(nnew - nstar), initial=0.0)) / max(float(np.max(np.abs(nnew), initial=0.0)), 1e-300)
        nstar = nstar + omega * (nnew - nstar)
        if change < tol:
            return {"status": "converged", "alpha": alpha, "iterations": it, "history": history,
                    "time_s": time.perf_counter() - t0}
    return {"status": "not_converged", "alpha": alpha, "iterations": max_iter, "history": history,
            "time_s": time.perf_counter() - t0, "reason": f"normal forces still changing after {max_iter} LPs"}
