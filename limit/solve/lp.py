"""Step 1: the associative (dilatant) limit analysis as linear programs, with cvxpy.

Static LP (lower-bound form, gives the contact actions)::

    maximise alpha  s.t.  Eh xh + alpha fLh = -f0h,   Yh xh <= kh

Kinematic LP (upper-bound form, gives the mechanism)::

    minimise -f0h . vh + kh . lamh  s.t.  Eh.T vh + Yh.T lamh = 0,  fLh . vh = 1,  lamh >= 0

(kh = 0 for dry joints; kh . lamh is the dissipation of cohesion and tension.)

Both are built in matrix form (one sparse matrix per constraint block) on the
scaled problem of :mod:`limit.model.assemble`. They are each other's duals: the
static LP's equality multipliers are the mechanism vh and its inequality
multipliers the plastic multipliers lamh, so one static solve yields the
mechanism too; the kinematic LP is solved on request as an independent check.
Unscaled: ``u = vh / Df`` (normalised to unit work of the live load,
``fL . u = 1``), ``lam = lamh / Sy``, ``x = Dx xh``.

Solvers (named in the registry :mod:`limit.solve.solvers`): through cvxpy ``clarabel`` (interior point, qdldl factorisation),
``ecos``, ``highs`` (HiGHS's own choice, dual simplex on LPs) and ``highs-ipm``;
and ``ipm`` (:mod:`limit.solve.ipm`), an interior point method that exploits the
interface-by-interface structure of the yield rows (2-4x faster than Clarabel
from a few thousand blocks on, no infeasibility detection: a run that does not
converge is "failed" and the next solver is asked). ``auto`` (the default) is
``ipm`` from the setting ``lp_ipm_min_dof`` block unknowns on (:mod:`limit.settings`) and ``clarabel`` below.
The defaults were chosen from ``make bench`` (see bench/lp_bench.py).
A solver's inaccurate or unknown status is never reported as optimal.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from limit import settings
from limit.model.assemble import Assembled
from limit.solve.status import IpmStatus, Status
from limit.solve.solvers import DEFAULT_SOLVER, FALLBACK, SOLVERS  # noqa: F401  (public here too)

#: solver name -> (cvxpy solver, options)
CVXPY_SOLVERS = {
    "clarabel": ("CLARABEL", {"direct_solve_method": "qdldl", "tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10,
                              "tol_feas": 1e-10, "tol_ktratio": 1e-8, "max_iter": 500}),
    "ecos": ("ECOS", {"abstol": 1e-9, "reltol": 1e-9, "feastol": 1e-9, "max_iters": 500}),
    "highs": ("HIGHS", {}),
    "highs-ipm": ("HIGHS", {"highs_options": {"solver": "ipm", "run_crossover": "off"}}),
}
assert set(CVXPY_SOLVERS) <= set(SOLVERS), "every cvxpy solver is named in limit.solve.solvers"


def resolve(solver: str, P: Assembled) -> str:
    """The solver that ``solver`` names for problem P ("auto" -> ipm or clarabel by size)."""
    if solver not in SOLVERS:
        raise ValueError(f"unknown solver {solver!r} (one of {', '.join(SOLVERS)})")
    if solver == "auto":
        return "ipm" if P.n_dof >= settings.of(P).lp_ipm_min_dof else "clarabel"
    return solver


@dataclass
class LPSolution:
    """Result of one LP solve (unscaled quantities; None where the status has none)."""

    status: Status                   # optimal | unbounded | infeasible | inaccurate | failed
    alpha: float | None = None
    x: np.ndarray | None = None      # interface actions (model components)
    u: np.ndarray | None = None      # mechanism, fL . u = 1
    lam: np.ndarray | None = None    # plastic multipliers, >= 0
    solver: str = ""
    cvxpy_status: str = ""
    reason: str = ""
    timings: dict = field(default_factory=dict)
    form: str = "static"


def _solve(prob: cp.Problem, solver: str, overrides: dict | None = None) -> tuple[str, dict]:
    name, opts = CVXPY_SOLVERS[solver]
    opts = {**opts, **(overrides or {})}
    t0 = time.perf_counter()
    try:
        prob.solve(solver=name, **opts)
        status = prob.status
    except (cp.error.SolverError, ValueError) as exc:
        # cvxpy raises ValueError ("Cannot unpack invalid solution") when a solver ends
        # with an unknown status (seen with HiGHS): a failed attempt, never a crash
        status = f"solver_error: {exc}"
    total = time.perf_counter() - t0
    stats = prob.solver_stats
    solve_t = getattr(stats, "solve_time", None) if stats is not None else None
    compile_t = getattr(prob, "compilation_time", None)
    t = {"compile_s": compile_t if compile_t is not None else float("nan"),
         "solve_s": solve_t if solve_t is not None else float("nan"), "solver_total_s": total}
    return status, t


def _map_status(status: str) -> tuple[Status, str]:
    if status == cp.OPTIMAL:
        return Status.OPTIMAL, ""
    if status == cp.UNBOUNDED:
        return Status.UNBOUNDED, ""
    if status == cp.INFEASIBLE:
        return Status.INFEASIBLE, ""
    if status in (cp.OPTIMAL_INACCURATE, cp.UNBOUNDED_INACCURATE, cp.INFEASIBLE_INACCURATE):
        return Status.INACCURATE, f"the solver reported {status}"
    return Status.FAILED, f"the solver reported {status}"


def static_lp(P: Assembled, solver: str = DEFAULT_SOLVER, overrides: dict | None = None) -> LPSolution:
    """Maximise alpha over statically admissible interface actions (``overrides``: solver options)."""
    solver = resolve(solver, P)
    if solver == "ipm":
        return _static_ipm(P, overrides)
    xh = cp.Variable(P.model.n_x)
    a = cp.Variable()
    eq = P.Eh @ xh + P.fLh * a == -P.f0h
    ineq = P.Yh @ xh <= P.kh
    prob = cp.Problem(cp.Maximize(a), [eq, ineq])
    status, t = _solve(prob, solver, overrides)
    st, reason = _map_status(status)
    sol = LPSolution(st, solver=solver, cvxpy_status=str(status), reason=reason, timings=t, form="static")
    if st in (Status.OPTIMAL, Status.INACCURATE) and xh.value is not None and eq.dual_value is not None:
        _unscale(P, sol, float(a.value), xh.value, eq.dual_value, ineq.dual_value)
    return sol


def _unscale(P: Assembled, sol: LPSolution, alpha, xh, vh, lamh) -> None:
    """Fill sol with the unscaled static solution: x = Dx xh; the mechanism u = vh / Df and
    lam = lamh / Sy, both divided by the live-load work fL . u (so that fL . u = 1)."""
    sol.alpha = float(alpha)
    sol.x = P.Dx * np.asarray(xh, dtype=float)
    u = np.asarray(vh, dtype=float) / P.Df
    work = float(P.fL @ u)
    if not (work != 0 and np.isfinite(work)):
        work = 1.0
    sol.u = u / work
    sol.lam = np.asarray(lamh, dtype=float) / P.Sy / work


#: :func:`limit.solve.ipm.solve`'s ``almost`` for the step-1 LP: when the method stalls short of its
#: tolerance (1e-9), its best iterate is returned as "inaccurate" if its largest relative residual
#: is at most this, and then checked like every LP answer (:func:`limit.solve.verify.check_lp`,
#: 1e-6). On the 30-block 3D wall of the catalog (paper model) the dual residual fell to 1.0e-9,
#: just above the tolerance, at iteration 14 (alpha 0.65 to 1e-10), then rose to 1e-4..1e-3 as mu
#: fell to 1e-22, and the method failed after 200 iterations
IPM_ALMOST = 1e-8


def _static_ipm(P: Assembled, overrides: dict | None = None) -> LPSolution:
    """The static LP by :mod:`limit.solve.ipm` (same unscaling as the cvxpy path); the method's
    "almost" answer (:data:`IPM_ALMOST`) is reported "inaccurate", to be verified by the caller."""
    from limit.solve import ipm
    r = ipm.solve(P.Eh, P.Yh, P.f0h, P.fLh, P.model.x_iface, c=P.kh, **{"almost": IPM_ALMOST, **(overrides or {})})
    t = {"compile_s": r["setup_s"], "solve_s": r["solve_s"] - r["setup_s"], "solver_total_s": r["solve_s"],
         "ipm_iterations": r["iterations"]}
    st = Status.INACCURATE if r["status"] == IpmStatus.ALMOST else Status(r["status"])  # ipm: optimal | failed | almost
    sol = LPSolution(st, solver="ipm", cvxpy_status=f"ipm {r['status']}", reason=r["reason"],
                     timings=t, form="static")
    if st in (Status.OPTIMAL, Status.INACCURATE):
        _unscale(P, sol, r["alpha"], r["xh"], r["vh"], r["lamh"])
    return sol


def kinematic_lp(P: Assembled, solver: str = DEFAULT_SOLVER) -> LPSolution:
    """Minimise the dead-load resistance over mechanisms with unit live-load work (cvxpy solvers only)."""
    solver = resolve(solver, P)
    if solver not in CVXPY_SOLVERS:
        solver = "clarabel"
    vh = cp.Variable(P.n_dof)
    lamh = cp.Variable(P.model.n_faces, nonneg=True)
    comp = P.Eh.T @ vh + P.Yh.T @ lamh == 0
    norm = P.fLh @ vh == 1
    prob = cp.Problem(cp.Minimize(-P.f0h @ vh + P.kh @ lamh), [comp, norm])
    status, t = _solve(prob, solver)
    st, reason = _map_status(status)
    # The kinematic LP is the dual: its "infeasible" means no mechanism (static unbounded) and
    # "unbounded" means collapse under the dead load (static infeasible).
    st = {Status.INFEASIBLE: Status.UNBOUNDED, Status.UNBOUNDED: Status.INFEASIBLE}.get(st, st)
    sol = LPSolution(st, solver=solver, cvxpy_status=str(status), reason=reason, timings=t, form="kinematic")
    if st in (Status.OPTIMAL, Status.INACCURATE) and vh.value is not None:
        sol.u = vh.value / P.Df
        sol.lam = lamh.value / P.Sy
        sol.alpha = float(-P.f0 @ sol.u + P.model.k @ sol.lam)
        if comp.dual_value is not None:
            sol.x = -P.Dx * np.asarray(comp.dual_value, dtype=float)
    return sol
