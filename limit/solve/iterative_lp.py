"""The iterative LP of Gilbert, Casapulla & Ahmed (Computers & Structures 84, 2006, 873-887).

An independent route to the frictional collapse factor: the Coulomb bound of
every sliding (and twisting) face, ``|V| <= mu N (+ c A)``, is replaced by a fixed
shear capacity ``|V| <= mu N* (+ c A)`` with N* the normal force of the previous
iteration, which makes the LP associative *without* dilatancy (the face no
longer involves N). After each LP, ``N* <- N* + omega (N - N*)`` (relaxation
omega), until the normal forces settle. The rocking faces are unchanged.
Started from the normal forces of the associative LP.

Backends: ``highs`` (any size; the independent check of the validation run) and
``ipm`` (:mod:`limit.solve.ipm`, the structured interior point method: only the
right-hand side of the friction rows changes, so the per-interface block
structure survives; the large-scale route of step 2, :mod:`limit.solve.step2_large`).
With ``ipm`` the result also carries the last LP's point (``xh``, ``vh``,
``lamh``: scaled actions, mechanism with fLh . vh = 1, multipliers) and
``nstar``, for the snap to a complementary point.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from limit.solve import lpsub
from limit.solve.status import IpmStatus, IterativeStatus
from limit.model.yield_domain import SLIDE, TWIST


@dataclass(frozen=True)
class IterativeResult:
    """The outcome of :func:`solve`. ``status``: :class:`IterativeStatus`; ``alpha``: the last LP's
    load factor (None when an LP failed or none ran); ``iterations``: LPs solved; ``history``: each
    LP's alpha; ``time_s``: seconds; ``reason``: why it did not converge (empty where it did).
    Backend ``ipm`` only: ``nstar`` (the last N*, scaled, one per friction row) and the last LP's
    point ``xh``, ``vh``, ``lamh`` (scaled actions, mechanism with fLh . vh = 1, multipliers)."""

    status: IterativeStatus
    alpha: float | None
    iterations: int
    history: list
    time_s: float
    reason: str = ""
    nstar: np.ndarray | None = field(default=None, repr=False)
    xh: np.ndarray | None = field(default=None, repr=False)
    vh: np.ndarray | None = field(default=None, repr=False)
    lamh: np.ndarray | None = field(default=None, repr=False)

    def entry(self) -> dict:
        """The result file's ``nlp.iterative_lp`` entry (docs/formats.md): status, alpha,
        iterations, time_s, reason (None where there is none)."""
        return {"status": self.status, "alpha": self.alpha, "iterations": self.iterations, "time_s": self.time_s,
                "reason": self.reason or None}


def _normal_columns(P, rows):
    """For each yield row, the column of the normal force it involves."""
    Y = P.Yh[rows].tocoo()
    is_n = P.model.normal_col[Y.col]
    col = np.full(len(rows), -1)
    col[Y.row[is_n]] = Y.col[is_n]
    coef = np.zeros(len(rows))
    coef[Y.row[is_n]] = Y.data[is_n]
    return col, coef


def friction_rows(P):
    """(fr, Yc, ncol, ncoef): the friction (sliding and twisting) yield rows, the scaled yield
    matrix with their normal-force terms removed, and for each friction row the column and
    coefficient of that term (-1 where none)."""
    kind = P.model.kind
    fr = np.flatnonzero((kind == SLIDE) | (kind == TWIST))
    ncol, ncoef = _normal_columns(P, fr)
    Y = P.Yh.tocoo()
    is_fr = np.zeros(P.Yh.shape[0], dtype=bool)
    is_fr[fr] = True
    col_of = np.full(P.Yh.shape[0], -1)
    col_of[fr] = ncol
    drop = is_fr[Y.row] & (Y.col == col_of[Y.row])
    Yc = sp.csr_matrix((Y.data[~drop], (Y.row[~drop], Y.col[~drop])), shape=P.Yh.shape)
    return fr, Yc, ncol, ncoef


def solve(P, lp_sol, omega: float = 0.5, tol: float = 1e-8, max_iter: int = 300, backend: str = "highs",
          nstar0: np.ndarray | None = None, on_iterate=None, lp_tol=None, warm_start: bool = False,
          prox: float | None = None) -> IterativeResult:
    """The iterative LP (:class:`IterativeResult`).

    ``nstar0``: the first N* (scaled, one per friction row; default: the LP's).
    ``on_iterate(it, r, nstar)`` (ipm backend): called after each LP with its result; a
    true return value stops the iteration (status "stopped"). With the ipm backend ``omega``
    may be a callable, asked before each update (an adaptive relaxation), and ``lp_tol`` (a
    number, or a callable asked before each LP) the interior point method's tolerance, and
    ``warm_start`` starts each LP from the last one's point (:func:`limit.solve.ipm.solve`'s
    ``warm``; cold when that fails). A warm start ends at another point of a degenerate LP's
    optimal face than the cold start's central one, and so changes the iteration's path:
    the confined block of scenes/builders.py stalled with it (0.625 without). ``prox`` (ipm
    backend; None: none): each LP becomes the QP ``max alpha - rho/2 sum (N - N*)^2`` over the
    normal forces of the friction rows, rho = prox / sum N*^2 (so that N = 0 throughout would
    cost prox/2 in alpha): among the statics of a degenerate optimal face it takes those nearest
    N*, and a fixed point N = N* is an exact LP optimum (the term and its gradient vanish there).
    A proximal point step (Rockafellar 1976) on the statics."""
    t0 = time.perf_counter()
    if backend == "ipm":
        return _solve_ipm(P, lp_sol, omega, tol, max_iter, nstar0, on_iterate, t0, lp_tol, warm_start, prox)
    # Yield rows with the normal-force term of the friction faces removed (moved to the right-hand side).
    fr, Yc, ncol, ncoef = friction_rows(P)
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
        b = P.kh.copy()  # a friction row's capacity kh - ncoef N* (ncoef < 0), never below 0
        b[fr] = np.maximum(P.kh[fr] - ncoef * nstar, 0.0)
        res = lpsub.solve(c, Aeq, -P.f0h, Aub, b, lo, hi, backend)
        if not res.ok:
            return IterativeResult(IterativeStatus.FAILED, None, it, history, time.perf_counter() - t0,
                                   f"LP {it}: {res.status}")
        alpha = float(res.z[0])
        nnew = res.z[1:][ncol]
        history.append(alpha)
        change = float(np.max(np.abs(nnew - nstar), initial=0.0)) / max(float(np.max(np.abs(nnew), initial=0.0)), 1e-300)
        nstar = nstar + omega * (nnew - nstar)
        if change < tol:
            return IterativeResult(IterativeStatus.CONVERGED, alpha, it, history, time.perf_counter() - t0)
    return IterativeResult(IterativeStatus.NOT_CONVERGED, alpha, max_iter, history, time.perf_counter() - t0,
                           f"normal forces still changing after {max_iter} LPs")


#: smallest N* of the ipm backend, relative to the largest (see _solve_ipm); an LP that does not
#: converge is tried again with the floor raised 100-fold, up to NSTAR_FLOOR_MAX (a 3,000-block
#: wall's first LP: not converged in 200 iterations at 1e-8, 37 iterations at 1e-6; a floor of
#: 1e-6 throughout slowed a 1,000-block wall's snap from 29 LPs to 86)
NSTAR_FLOOR = 1e-8
NSTAR_FLOOR_MAX = 1e-4
#: Gondzio's centrality correctors in each LP of the ipm backend (ipm.solve's ``correctors``): none.
#: An LP whose optimal face is more than one point returns another point of it with them (they
#: centre less), and the point taken steers the iteration: with them the confined block of
#: scenes/builders.py diverges and the large walls' route needs more LPs (docs/performance.md,
#: 'Measurements moved from code comments')
ITERATIVE_CORRECTORS = 0
#: ipm.solve's ``almost`` in each LP: an LP whose residuals stall short of its tolerance but below
#: this gives its best iterate (each iterate is checked independently, and only a snapped,
#: checked point is ever reported). Without it a 12-block 3D wall (4 x 3 running bond, mu 0.7)
#: failed every start: LP 4 stalled at residuals of 1e-8 to 8e-7 for 200 iterations, at each
#: raised floor N* as well
ITERATIVE_ALMOST = 1e-6
#: the statuses of ipm.solve taken as an answer
_OK = (IpmStatus.OPTIMAL, IpmStatus.ALMOST)


def _proximal(P, ncol, nstar, prox) -> dict:
    """The ipm keywords (q, x_ref) of the proximal term of :func:`solve` (``prox``) about N*."""
    ok = ncol >= 0
    ucol = np.unique(ncol[ok])
    x_ref = np.zeros(P.model.n_x)
    x_ref[ncol[ok]] = nstar[ok]  # one N* per friction row; the rows of one normal force share it
    q = np.zeros(P.model.n_x)
    q[ucol] = prox / max(float(x_ref[ucol] @ x_ref[ucol]), 1e-300)
    return {"q": q, "x_ref": x_ref}


def _solve_ipm(P, lp_sol, omega, tol, max_iter, nstar0, on_iterate, t0, lp_tol=None, warm_start=False,
               prox=None) -> IterativeResult:
    from limit.solve import ipm
    fr, Yc, ncol, ncoef = friction_rows(P)
    nstar = (lp_sol.x / P.Dx)[ncol] if nstar0 is None else np.asarray(nstar0, float).copy()
    history, r, it, status, warm = [], None, 0, IterativeStatus.NOT_CONVERGED, None
    structure = ipm.Structure(P.Eh, Yc, P.model.x_iface)  # the same matrices in every LP
    for it in range(1, max_iter + 1):
        c = P.kh.copy()
        # a joint that opened (N* = 0) keeps a sliver of shear capacity: with none, its two
        # sliding faces pin the shear at zero and the interior point method has no interior
        rel = NSTAR_FLOOR
        while True:
            floor = rel * max(float(np.max(nstar, initial=0.0)), 1e-300)
            c[fr] = P.kh[fr] - ncoef * np.maximum(nstar, floor)
            t_lp = lp_tol() if callable(lp_tol) else lp_tol
            kw = {} if t_lp is None else {"tol": t_lp}
            if prox:
                kw.update(_proximal(P, ncol, nstar, prox))
            kw.update(correctors=ITERATIVE_CORRECTORS, structure=structure, almost=ITERATIVE_ALMOST)
            r = None
            if warm is not None and warm_start and rel == NSTAR_FLOOR:  # from the last LP's point; cold if that
                # fails, and cold at every raised floor (a changed LP, far from the last point)
                r = ipm.solve(P.Eh, Yc, P.f0h, P.fLh, P.model.x_iface, c=c, warm=warm, **kw)
            if r is None or r["status"] not in _OK:
                r = ipm.solve(P.Eh, Yc, P.f0h, P.fLh, P.model.x_iface, c=c, **kw)
            if r["status"] in _OK or rel >= NSTAR_FLOOR_MAX:
                break
            rel *= 100.0
        if r["status"] not in _OK:
            return IterativeResult(IterativeStatus.FAILED, None, it, history, time.perf_counter() - t0,
                                   f"LP {it}: {r['reason']}")
        history.append(float(r["alpha"]))
        warm = r
        nnew = r["xh"][ncol]
        change = float(np.max(np.abs(nnew - nstar), initial=0.0)) / max(float(np.max(np.abs(nnew), initial=0.0)), 1e-300)
        if on_iterate is not None and on_iterate(it, r, nstar):
            status = IterativeStatus.STOPPED
            break
        nstar = nstar + (omega() if callable(omega) else omega) * (nnew - nstar)
        if change < tol:
            status = IterativeStatus.CONVERGED
            break
    last = {} if r is None else {"xh": r["xh"], "vh": r["vh"], "lamh": r["lamh"]}
    why = f"normal forces still changing after {max_iter} LPs" if status == IterativeStatus.NOT_CONVERGED else ""
    return IterativeResult(status, history[-1] if history else None, it, history, time.perf_counter() - t0, why,
                           nstar, **last)
