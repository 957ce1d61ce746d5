"""A small sparse LP front end for the NLP's subproblems and the independent checks.

``solve(c, Aeq, beq, Aub, bub, lo, hi, backend)`` minimises ``c . z`` subject to
``Aeq z = beq``, ``Aub z <= bub`` and ``lo <= z <= hi`` (infinite bounds
allowed). Backends: ``"highs"`` (scipy.optimize.linprog, HiGHS, exact vertex
solutions; fine up to a few thousand unknowns) and ``"clarabel"`` (interior
point through Clarabel's own sparse API: no cvxpy compile on every call; for
large problems).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog

from limit.solve.solvers import SUBPROBLEM_BACKENDS


#: Clarabel statuses that prove an LP has no optimum (infeasible, or unbounded: its dual infeasible)
CLARABEL_NO_POINT = ("PrimalInfeasible", "AlmostPrimalInfeasible", "DualInfeasible", "AlmostDualInfeasible")
#: scipy.optimize.linprog statuses that do: 2 infeasible, 3 unbounded (HiGHS's "unbounded or
#: infeasible" shares 4 with numerical failures, so it is not counted)
LINPROG_NO_POINT = (2, 3)


class LPResult:
    """``ok``, ``z`` (the optimum, None unless ok), the backend's ``status`` text, the objective
    ``fun``, and ``no_point``: the backend proved the LP infeasible or unbounded (so no other
    backend can give an optimum; a time limit or numerical failure proves nothing)."""

    def __init__(self, ok, z=None, status="", fun=None, no_point=False):
        self.ok, self.z, self.status, self.fun, self.no_point = ok, z, status, fun, no_point


def solve(c, Aeq, beq, Aub, bub, lo, hi, backend: str = "highs", tol: float = 1e-9,
          time_limit: float | None = None, almost: bool = False) -> LPResult:
    """``time_limit`` (s, None: none): the backend stops there and the answer is not ok.
    ``almost``: Clarabel's "AlmostSolved" (reduced accuracy) counts as ok, for callers whose
    answer is checked independently anyway (the snap of :mod:`limit.solve.step2_large`)."""
    if time_limit is not None and time_limit <= 0:
        return LPResult(False, None, "time limit reached before the LP")
    if backend == "highs":
        bounds = np.column_stack([np.where(np.isfinite(lo), lo, -np.inf), np.where(np.isfinite(hi), hi, np.inf)])
        opts = {"primal_feasibility_tolerance": tol, "dual_feasibility_tolerance": tol}
        if time_limit is not None:
            opts["time_limit"] = float(time_limit)
        res = linprog(c, A_ub=Aub, b_ub=bub, A_eq=Aeq, b_eq=beq, bounds=bounds, method="highs", options=opts)
        return LPResult(res.status == 0, res.x if res.status == 0 else None, res.message, res.fun,
                        no_point=res.status in LINPROG_NO_POINT)
    if backend == "clarabel":
        return _clarabel(c, Aeq, beq, Aub, bub, lo, hi, tol, time_limit, almost)
    raise ValueError(f"unknown LP backend {backend!r} (one of {', '.join(SUBPROBLEM_BACKENDS)})")


def _clarabel(c, Aeq, beq, Aub, bub, lo, hi, tol, time_limit=None, almost=False):
    import clarabel

    n = len(c)
    rows, rhs = [sp.csr_matrix(Aeq)], [np.asarray(beq, float)]
    neq = Aeq.shape[0]
    ub_rows, ub_rhs = [sp.csr_matrix(Aub)], [np.asarray(bub, float)]
    flo = np.flatnonzero(np.isfinite(lo))
    fhi = np.flatnonzero(np.isfinite(hi))
    if flo.size:
        ub_rows.append(sp.csr_matrix((-np.ones(flo.size), (np.arange(flo.size), flo)), shape=(flo.size, n)))
        ub_rhs.append(-lo[flo])
    if fhi.size:
        ub_rows.append(sp.csr_matrix((np.ones(fhi.size), (np.arange(fhi.size), fhi)), shape=(fhi.size, n)))
        ub_rhs.append(hi[fhi])
    A = sp.vstack(rows + ub_rows).tocsc()
    b = np.concatenate(rhs + ub_rhs)
    nub = A.shape[0] - neq
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.direct_solve_method = "qdldl"
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = max(tol, 1e-10)
    if time_limit is not None:
        settings.time_limit = float(time_limit)
    cones = ([clarabel.ZeroConeT(neq)] if neq else []) + ([clarabel.NonnegativeConeT(nub)] if nub else [])
    solver = clarabel.DefaultSolver(sp.csc_matrix((n, n)), np.asarray(c, float), A, b, cones, settings)
    sol = solver.solve()
    ok = str(sol.status) == "Solved" or (almost and str(sol.status) == "AlmostSolved")
    z = np.array(sol.x) if ok else None
    return LPResult(ok, z, str(sol.status), float(np.dot(c, z)) if ok else None,
                    no_point=str(sol.status) in CLARABEL_NO_POINT)


class HighsLP:
    """One LP kept in HiGHS across solves that change only the objective.

    Successive-linearisation steps keep the constraints and change the costs, so
    HiGHS restarts from the previous optimal basis (a few pivots instead of a
    cold solve).
    """

    def __init__(self, Aeq, beq, Aub, bub, lo, hi, tol: float = 1e-9):
        import highspy

        self._hs = highspy
        A = sp.vstack([sp.csr_matrix(Aeq), sp.csr_matrix(Aub)]).tocsc()
        n = A.shape[1]
        inf = highspy.kHighsInf
        lp = highspy.HighsLp()
        lp.num_col_ = n
        lp.num_row_ = A.shape[0]
        lp.col_cost_ = np.zeros(n)
        lp.col_lower_ = np.where(np.isfinite(lo), lo, -inf)
        lp.col_upper_ = np.where(np.isfinite(hi), hi, inf)
        lp.row_lower_ = np.concatenate([np.asarray(beq, float), np.full(Aub.shape[0], -inf)])
        lp.row_upper_ = np.concatenate([np.asarray(beq, float), np.asarray(bub, float)])
        lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
        lp.a_matrix_.start_ = A.indptr
        lp.a_matrix_.index_ = A.indices
        lp.a_matrix_.value_ = A.data
        h = highspy.Highs()
        h.setOptionValue("output_flag", False)
        h.setOptionValue("primal_feasibility_tolerance", tol)
        h.setOptionValue("dual_feasibility_tolerance", tol)
        h.passModel(lp)
        self.h, self.n = h, n
        self._idx = np.arange(n, dtype=np.int32)

    def cold(self) -> None:
        """Forget the basis: the next solve starts cold, not from the previous solve's basis."""
        self.h.clearSolver()

    def solve(self, c) -> LPResult:
        h = self.h
        h.changeColsCost(self.n, self._idx, np.asarray(c, dtype=float))
        h.run()
        st = h.getModelStatus()
        if st != self._hs.HighsModelStatus.kOptimal:
            return LPResult(False, None, h.modelStatusToString(st))
        z = np.array(h.getSolution().col_value)
        return LPResult(True, z, "optimal", float(np.dot(c, z)))
