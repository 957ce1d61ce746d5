"""The two-step limit analysis of a scene, producing the result file of docs/formats.md, 'Result file'.

Step 1 (:func:`solve_lp`): the associative LP, verified a posteriori
(:mod:`limit.verify`); an answer that fails its checks is re-solved with the
next solver and, if none passes, reported as "failed" with the reasons.
Step 2 (NLP, :mod:`limit.nlp`) is added by :func:`analyse` according to the method.
"""
from __future__ import annotations

import time

import numpy as np

from . import lp as lpmod
from . import mechanism, verify
from .assemble import Assembled, Options, assemble


def solve_lp(P: Assembled, solver: str = lpmod.DEFAULT_SOLVER, fallback: bool = True,
             check_kinematic: bool = False) -> tuple[lpmod.LPSolution, list, dict]:
    """Solve and verify the static LP; returns (solution, attempts, residuals).

    ``solution.status``: optimal | unbounded | infeasible | failed. alpha < 0
    (collapse under the dead load alone) is reported as "infeasible".
    """
    solver = lpmod.resolve(solver, P)  # ValueError for an unknown name
    attempts = []
    if P.n_dof == 0 or not np.any(P.fL):
        sol = lpmod.LPSolution("unbounded", solver=solver,
                               reason="the live load does no work on any free block: no mechanism can be driven")
        return sol, attempts, {}
    loose = unsupported_blocks(P)
    if loose:
        more = f" and {len(loose) - 5} more" if len(loose) > 5 else ""
        sol = lpmod.LPSolution("infeasible", solver="-", reason=(
            f"block(s) {', '.join(loose[:5])}{more} touch no other block, so nothing carries their dead load "
            f"(a gap wider than the contact tolerance, {P.scene.tolerance:.3g} m?)"))
        return sol, attempts, {}
    chain = [solver] + (lpmod.FALLBACK.get(solver, []) if fallback else [])
    residuals = {}
    verdicts = []
    for name in chain:
        sol = lpmod.static_lp(P, name)
        t0 = time.perf_counter()
        if sol.status in ("optimal", "inaccurate"):
            ok, residuals, why = verify.check_lp(P, sol)
            sol.timings["verify_s"] = time.perf_counter() - t0
            attempts.append({"solver": name, "status": sol.cvxpy_status, "verified": ok, "reason": why,
                             "alpha": sol.alpha})
            if ok:
                sol.status = "optimal"
                break
            sol.status, sol.reason = "failed", f"{name}: {sol.cvxpy_status} but {why}"
        else:
            attempts.append({"solver": name, "status": sol.cvxpy_status, "verified": False, "reason": sol.reason})
            if sol.status in ("unbounded", "infeasible"):
                verdicts.append(sol.status)
                if len(verdicts) >= 2 or not fallback or name == chain[-1]:
                    break  # two solvers agree (or no one left to ask)
            if sol.status == "failed":
                sol.reason = f"{name}: {sol.reason}"
    if sol.status == "failed":
        sol.alpha = None  # a rejected number is kept only in the attempts list
    if sol.status in ("unbounded", "infeasible") and len(set(verdicts)) > 1:
        sol.status, sol.reason = "failed", f"solvers disagree: {verdicts}"
    if sol.status == "unbounded" and not sol.reason:
        sol.reason = "no collapse mechanism under this live load (alpha unbounded)"
    if sol.status == "infeasible" and not sol.reason:
        sol.reason = "the dead load alone cannot be carried"
    if sol.status == "optimal" and sol.alpha < -verify.TOL_GAP:
        sol.status = "infeasible"
        sol.reason = f"collapses under the dead load alone (the live load would have to act backwards, alpha = {sol.alpha:.6g})"
    if sol.status == "optimal" and check_kinematic:
        names = [sol.solver] + [c for c in chain if c != sol.solver]
        for name in [n for n in names if n in lpmod.CVXPY_SOLVERS] or ["clarabel"]:
            kin = lpmod.kinematic_lp(P, name)
            if kin.status == "optimal":
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


def lp_result(P: Assembled, sol, attempts, residuals, t_total: float) -> dict:
    """The ``lp`` part of the result file."""
    t = dict(P.timings)
    t.update({k: v for k, v in sol.timings.items()})
    out = {"status": sol.status, "alpha": sol.alpha if sol.status == "optimal" else None,
           "time_s": t_total, "solver": sol.solver, "timings": t, "attempts": attempts,
           "model": {"interfaces": P.options.model, "n_slide": P.options.n_slide,
                     "slide_fit": P.options.slide_fit}}
    if sol.reason:
        out["reason"] = sol.reason
    if sol.status == "infeasible" and sol.alpha is not None:
        out["alpha_free"] = sol.alpha
    if sol.status == "optimal":
        out["verification"] = residuals
        out["mechanism"] = mechanism.per_block(P, sol.u)
        out["normalisation"] = "unit work of the live load: fL . u = 1"
        cls = mechanism.classify(P, sol.u)
        out["interfaces"] = interfaces_part(P, P.model.H @ sol.x, cls)
        out["counts"] = {k: int(v.sum()) for k, v in cls.items()}
    return out


def interfaces_part(P, r, cls) -> dict:
    """Interface pairs, their generalised stresses (local frame) and motion flags."""
    nq = P.scene.ndof
    return {
        "pairs": [list(p) for p in P.I.pairs(P.scene)],
        "stress_components": ["V", "N", "M"] if P.scene.dim == 2 else ["V1", "V2", "N", "M1", "M2", "T"],
        "stress": np.asarray(r).reshape(-1, nq).tolist(),
        **{k: np.flatnonzero(v).tolist() for k, v in cls.items()},
    }


def analyse(scene, method: str = "auto", options: Options | None = None, solver: str = lpmod.DEFAULT_SOLVER,
            fallback: bool = True, check_kinematic: bool = False, nlp_options: dict | None = None) -> dict:
    """Full analysis of a scene: the result dict of docs/formats.md, 'Result file' (without ``dem``).

    BLAS runs on one thread meanwhile (threadpoolctl, restored on return): the dense algebra
    here is small (SLSQP, 2x2 to 6x6 blocks), runs are parallelised by process, and a
    multi-threaded OpenBLAS on a busy machine was measured to slow SLSQP down 300-fold."""
    if method not in ("lp", "nlp", "auto"):
        raise ValueError(f"method must be lp, nlp or auto, not {method!r}")
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options)


def _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options) -> dict:
    t0 = time.perf_counter()
    P = assemble(scene, options)
    sol, attempts, residuals = solve_lp(P, solver, fallback, check_kinematic)
    out = {"scene": scene.name, "dim": scene.dim, "n_blocks": scene.n_blocks,
           "n_free_blocks": int(len(scene.free)), "n_interfaces": len(P.I)}
    out["lp"] = lp_result(P, sol, attempts, residuals, time.perf_counter() - t0)
    if method != "lp":
        from . import nlp

        out["nlp"] = nlp.step2(P, sol, method=method, **(nlp_options or {}))
        if out["nlp"].get("status") == "optimal" and out["nlp"].get("alpha") is not None and \
                out["nlp"]["alpha"] < -verify.TOL_GAP:
            out["nlp"]["status"] = "infeasible"
    out["_assembled"] = P
    out["_lp_solution"] = sol
    return out


def public(result):
    """The result without the in-memory objects (keys starting with '_', at any depth)."""
    if isinstance(result, dict):
        return {k: public(v) for k, v in result.items() if not str(k).startswith("_")}
    return result
