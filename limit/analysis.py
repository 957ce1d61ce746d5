"""The two-step limit analysis of a scene: :class:`Analysis`, the result file of docs/formats.md,
'Result file', with the assembled problem and the LP solution it is made from.

Step 1: the checked associative LP (:mod:`limit.solve.checked_lp`). Step 2 (NLP,
:mod:`limit.step2`) is added by :func:`analyse` according to the method. The result's
parts are built by :mod:`limit.results.result_parts`.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

from limit import step2
from limit.solve.status import Status
from limit.solve import lp as lpmod
from limit.model.assemble import Assembled, Options, assemble
from limit.solve.checked_lp import solve_lp, unsupported_blocks  # noqa: F401  (public here too)
from limit.results.result_parts import interfaces_part, lp_result  # noqa: F401


#: units of every number in a result, whatever the scene file's ``units`` (converted on reading)
RESULT_UNITS = {"length": "m", "mass": "kg", "force": "N", "time": "s"}


@dataclass(frozen=True)
class Analysis:
    """One analysis: ``data``, the result file's content (plain JSON-ready values only), beside
    the objects it is made from: ``P``, the assembled problem, and ``sol``, step 1's LP solution."""

    data: dict
    P: Assembled
    sol: lpmod.LPSolution


def analyse(scene, method: str = "auto", options: Options | None = None, solver: str = lpmod.DEFAULT_SOLVER,
            fallback: bool = True, check_kinematic: bool = False, nlp_options: dict | None = None,
            verdict: bool = True) -> Analysis:
    """Full analysis of a scene: its :class:`Analysis`, whose ``data`` is the result file of
    docs/formats.md, 'Result file' (without ``dem``).
    ``verdict`` False: no code check even where the scene states a demand (a caller that
    checks against another demand).

    BLAS runs on one thread meanwhile (threadpoolctl, restored on return): the dense algebra
    here is small (SLSQP, 2x2 to 6x6 blocks), runs are parallelised by process, and a
    multi-threaded OpenBLAS on a busy machine was measured to slow SLSQP down 300-fold."""
    if method not in ("lp", "nlp", "auto"):
        raise ValueError(f"method must be lp, nlp or auto, not {method!r}")
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options, verdict)


def _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options, verdict=True) -> Analysis:
    t0 = time.perf_counter()
    P = assemble(scene, options)
    sol, attempts, residuals = solve_lp(P, solver, fallback, check_kinematic)
    out = {"scene": scene.name, "dim": scene.dim, "n_blocks": scene.n_blocks,
           "n_free_blocks": int(len(scene.free)), "n_interfaces": len(P.I), "units": dict(RESULT_UNITS)}
    lp = lp_result(P, sol, attempts, residuals, time.perf_counter() - t0)
    out["lp"] = _with_dead_mechanism(P, lp) if sol.status == Status.INFEASIBLE else lp
    if method != "lp":
        out["nlp"] = step2.step2(P, sol, method=method, **(nlp_options or {}))
    if P.I.bonded and sol.status == Status.OPTIMAL:  # with cohesion the frictional alpha has a lower bound
        from limit.solve import radenkovic

        out["lower_bound"] = radenkovic.lower_bound(P, solver)
    if verdict and scene.demand is not None:  # the code check, only for a scene that states a demand
        from limit.incremental_curve import follow_frictional
        from limit.verdict.local_check import scene_verdict

        out["verdict"] = scene_verdict(scene, out, sliding=follow_frictional)
    return Analysis(out, P, sol)


def _with_dead_mechanism(P, lp: dict) -> dict:
    """An "infeasible" LP part with the dead-load mechanism (:mod:`limit.solve.dead_mechanism`) as
    ``dead_load_mechanism`` and its blocks and joints named in the reason (a new dict; ``lp``
    itself where there is no such mechanism)."""
    from limit.solve import dead_mechanism

    u = dead_mechanism.solve(P)
    if u is None:
        return lp
    part = dead_mechanism.describe(P, u)
    return {**lp, "dead_load_mechanism": part,
            "reason": f"{lp.get('reason') or 'the dead load alone cannot be carried'}; {dead_mechanism.phrase(part)}"}

