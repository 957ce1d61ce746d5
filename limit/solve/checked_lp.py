"""Step 1, checked: the associative LP solved and verified a posteriori (:mod:`limit.solve.verify`);
an answer that fails its checks is re-solved with the next solver and, if none passes,
reported as "failed" with the reasons. Used by the analysis and by step 2's starts."""
from __future__ import annotations

import time

import numpy as np

from limit import settings
from limit.solve import lp as lpmod, verify
from limit.model.assemble import Assembled
from limit.solve.status import Status


def solve_lp(P: Assembled, solver: str = lpmod.DEFAULT_SOLVER, fallback: bool = True,
             check_kinematic: bool = False) -> tuple[lpmod.LPSolution, list, dict]:
    """Solve and verify the static LP; returns (solution, attempts, residuals).

    ``solution.status``: optimal | unbounded | infeasible | failed. alpha < 0
    (collapse under the dead load alone) is reported as "infeasible".
    """
    solver = lpmod.resolve(solver, P)  # ValueError for an unknown name
    attempts = []
    if P.n_dof == 0 or not np.any(P.fL):
        sol = lpmod.LPSolution(Status.UNBOUNDED, solver=solver,
                               reason="the live load does no work on any free block: no mechanism can be driven")
        return sol, attempts, {}
    loose = unsupported_blocks(P)
    if loose:
        from limit.model.pair_checks import gap_phrase

        more = f" and {len(loose) - 5} more" if len(loose) > 5 else ""
        first = P.scene.block_index()[loose[0]]
        sol = lpmod.LPSolution(Status.INFEASIBLE, solver="-", reason=(
            f"block(s) {', '.join(loose[:5])}{more} touch no other block, so nothing carries their dead load: "
            f"for '{loose[0]}', {gap_phrase(P.scene, first)}"))
        return sol, attempts, {}
    chain = [solver] + (lpmod.FALLBACK.get(solver, []) if fallback else [])
    residuals = {}
    verdicts = []
    for name in chain:
        sol = lpmod.static_lp(P, name)
        t0 = time.perf_counter()
        if sol.status in (Status.OPTIMAL, Status.INACCURATE):
            ok, residuals, why = verify.check_lp(P, sol)
            sol.timings["verify_s"] = time.perf_counter() - t0
            attempts.append({"solver": name, "status": sol.cvxpy_status, "verified": ok, "reason": why,
                             "alpha": sol.alpha})
            if ok:
                sol.status = Status.OPTIMAL
                break
            sol.status, sol.reason = Status.FAILED, f"{name}: {sol.cvxpy_status} but {why}"
        else:
            attempts.append({"solver": name, "status": sol.cvxpy_status, "verified": False, "reason": sol.reason})
            if sol.status in (Status.UNBOUNDED, Status.INFEASIBLE):
                verdicts.append(sol.status)
                if len(verdicts) >= 2 or not fallback or name == chain[-1]:
                    break  # two solvers agree (or no one left to ask)
            if sol.status == Status.FAILED:
                sol.reason = f"{name}: {sol.reason}"
    if sol.status == Status.FAILED:
        sol.alpha = None  # a rejected number is kept only in the attempts list
    if sol.status in (Status.UNBOUNDED, Status.INFEASIBLE) and len(set(verdicts)) > 1:
        sol.status, sol.reason = Status.FAILED, f"solvers disagree: {verdicts}"
    if sol.status == Status.UNBOUNDED and not sol.reason:
        sol.reason = "no collapse mechanism under this live load (alpha unbounded)"
    if sol.status == Status.INFEASIBLE and not sol.reason:
        sol.reason = "the dead load alone cannot be carried"
    if sol.status == Status.OPTIMAL and sol.alpha < -settings.of(P).tol_gap:
        sol.status = Status.INFEASIBLE
        sol.reason = f"collapses under the dead load alone (the live load would have to act backwards, alpha = {sol.alpha:.6g})"
    if sol.status == Status.OPTIMAL and check_kinematic:
        names = [sol.solver] + [c for c in chain if c != sol.solver]
        for name in [n for n in names if n in lpmod.CVXPY_SOLVERS] or ["clarabel"]:
            kin = lpmod.kinematic_lp(P, name)
            if kin.status == Status.OPTIMAL:
                break
        residuals["alpha_kinematic_lp"] = kin.alpha
        residuals["kinematic_lp_status"] = kin.status
        residuals["kinematic_lp_solver"] = kin.solver
    return sol, attempts, residuals


def unsupported_blocks(P: Assembled) -> list[str]:
    """Ids of the free blocks with a dead load that touch no other block (no interface)."""
    touched = np.zeros(len(P.scene.blocks), bool)
    touched[P.I.a] = True
    touched[P.I.b] = True
    dead = np.abs(P.full(P.f0)).reshape(len(P.scene.free), -1).max(axis=1) > 0
    return [P.scene.blocks[i].id for i, d in zip(P.scene.free, dead) if d and not touched[i]]
