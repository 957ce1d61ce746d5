"""Step 2's policy: which route runs (the successive LP of :mod:`limit.solve.nlp` with its
restarts, or the large-scale route of :mod:`limit.solve.step2_large`), the independent checks
(global MILP, iterative LP) and the ``nlp`` part of the result file (docs/formats.md,
'Result file'). The algorithms themselves are in :mod:`limit.solve.nlp`. The size thresholds,
budgets and margins are settings (:mod:`limit.settings`), read from the problem's options."""
from __future__ import annotations

import logging
import time

import numpy as np

from limit import settings
from limit.solve.status import ANSWERED, Status
from limit.solve import iterative_lp, lpsub, mechanism, milp, nlp, nlp_starts, step2_large
from limit.solve.nlp_problem import build
from limit.solve.outcome import RouteOutcome
from limit.results.result_parts import interfaces_part, ties_part
from limit.results.typed import StepResult


log = logging.getLogger(__name__)

ALL_STRATEGIES = ("penalty", "random", "friction", "vertex", "coarse")
#: a budget or time limit given as this is the setting's (nlp_time_budget, global_time_limit)
FROM_SETTINGS = "settings"


def run(P, lp_sol, solver: str = "auto", start: str = "lp", backend: str = "auto", seed: int = 0,
        restarts: bool = True, strategies=ALL_STRATEGIES, time_budget: float | None | str = FROM_SETTINGS,
        verified_elsewhere: bool = False) -> RouteOutcome:
    """Solve step 2 from the given start; returns its :class:`RouteOutcome` (not yet the result part).

    From the LP start the primary solver (SLSQP up to the setting ``slsqp_max_vars`` unknowns,
    SLA otherwise) runs first. With ``restarts`` the SLA also runs from the same start with
    initial penalties 1, 0.1 and 0.01 (a low penalty lets it wander further before
    complementarity is enforced), a few times with random positive costs on the
    multipliers (nlp_starts.RANDOM_RESTARTS, by ``many_restarts_max_vars``; seeded, reproducible), and from the associative
    LPs at reduced friction (:func:`limit.solve.nlp_starts.reduced_friction_starts`). Where none of
    these verifies, it runs from the LP's simplex vertex (:func:`_vertex_plan`, strategy "vertex")
    and then from the coarser friction polygon (:func:`_coarse_plan`, "coarse"). The problem is
    non-convex: each run ends at a local solution; the lowest alpha that passes
    the independent check is kept and every run is listed. ``time_budget`` (s, None:
    none, "settings": ``nlp_time_budget``): once it is spent and a verified point is in hand,
    the run in progress stops and the runs left are listed as not begun; without a verified
    point the plan goes on up to ``hard_factor`` budgets (a result that fails then says so).
    The LPs are HiGHS's up to ``highs_max_vars`` unknowns, else Clarabel's (``backend`` "auto").
    ``verified_elsewhere``: another route has a verified point already, so this one stops at the
    budget as if it had one itself.
    """
    t0 = time.perf_counter()
    st = settings.of(P)
    if time_budget == FROM_SETTINGS:
        time_budget = st.nlp_time_budget
    deadline = None if time_budget is None else t0 + time_budget
    hard = None if time_budget is None else t0 + st.hard_factor * time_budget
    N = build(P)
    if backend == "auto":
        backend = "highs" if N.n <= st.highs_max_vars else "clarabel"
    if solver == "auto":
        solver = "slsqp" if N.n <= st.slsqp_max_vars else "sla"
    rng = np.random.default_rng(seed)
    if start == "lp":
        z0, why = nlp.phase1(N, nlp_starts.lp_start(N, lp_sol), backend)
        if z0 is None:
            return RouteOutcome(False, reason=f"no non-associative mechanism from the LP start ({why})",
                                solver=solver, time_s=time.perf_counter() - t0)
        label = "lp"
    else:
        z0, label = nlp_starts.arbitrary_start(N, seed), "arbitrary"
    plan = [(label, z0, solver, 1.0, None)]
    strategies = set(strategies) if restarts else set()
    if "penalty" in strategies:
        plan += [(label, z0, "sla", r, None) for r in (1.0, 0.1, 0.01) if (solver, 1.0) != ("sla", r)]
    if "random" in strategies:
        n_random = nlp_starts.RANDOM_RESTARTS[0 if N.n <= st.many_restarts_max_vars else 1]
        s0 = np.maximum(N.slack(z0), 0.0)
        scale = float(s0.mean()) if s0.size and s0.mean() > 0 else 1.0
        for _ in range(n_random):
            plan.append((label, z0, "sla", float(rng.choice([1.0, 0.1, 0.01])),
                         0.2 * scale * rng.uniform(0, 1, P.model.n_faces)))
    if "friction" in strategies:
        for lab, zs in nlp_starts.reduced_friction_starts(P, N, backend):
            plan += [(lab, zs, "sla", r, None) for r in (1.0, 0.1, 0.01)]
    lp = None
    if backend == "highs" and any(p[2] == "sla" for p in plan):
        lo, hi = N.bounds()
        lo[N.ia] = 0.0
        lp = lpsub.HighsLP(N.Aeq, N.beq, N.Yx, N.kh, lo, hi)
    runs, best = [], None
    fallbacks = []  # (what, plan maker): run in turn, each once, while no point has verified
    if "vertex" in strategies and start == "lp" and lp_sol.solver not in nlp_starts.VERTEX_SOLVERS:
        fallbacks.append(("from the LP's simplex vertex", lambda: _vertex_plan(P, N, lp_sol, backend, runs)))
    if "coarse" in strategies and nlp_starts.coarse_slide_faces(P) is not None:
        fallbacks.append(("from the coarser friction polygon",
                          lambda: _coarse_plan(P, N, solver, backend, seed, strategies, hard, runs)))
    k = -1
    while True:
        k += 1
        while k == len(plan) and fallbacks and not (best is not None and best[1]) \
                and (hard is None or time.perf_counter() < hard):
            if lp is not None:
                lp.cold()  # a fallback's first run starts from a cold basis, not the last failed run's
            what, make = fallbacks.pop(0)
            log.info("step 2: none of %d runs verified; %s", k, what)
            plan += make()
        if k >= len(plan):
            break
        lab, zs, name, rho0, jitter = plan[k]
        t1 = time.perf_counter()
        have = verified_elsewhere or (best is not None and best[1])  # a verified point in hand
        if deadline is not None and best is not None and (have and t1 > deadline or t1 > hard):
            spent = time_budget if have else st.hard_factor * time_budget
            runs.append({"start": lab, "solver": name, "not_run": len(plan) - k,
                         "reason": f"time budget of {spent:g} s spent: {len(plan) - k} run(s) not begun"})
            break
        if name == "slsqp":
            z, note = nlp.solve_slsqp(N, zs)
        elif name == "sla":
            z, note = nlp.solve_sla(N, zs, backend, rho0=rho0, lp=lp, jitter=jitter, deadline=deadline if have else hard)
        else:
            raise ValueError(f"unknown NLP solver {name!r} (slsqp, sla or auto)")
        alpha_raw = float(z[N.ia])
        zf, ok, res, why, pnote = nlp.finish(N, z, lp_sol.alpha, backend)
        run = {"start": lab, "solver": name, "rho0": rho0, "random": jitter is not None, "alpha": float(zf[N.ia]),
               "alpha_raw": alpha_raw, "verified": ok, "reason": why, "notes": [note, pnote],
               "time_s": time.perf_counter() - t1}
        runs.append(run)
        log.info("step 2: run %d of %d (%s start, %s%s): alpha %.6g, %s (%.1f s)", k + 1, len(plan), lab, name,
                 "" if name != "sla" else f", penalty {rho0:g}", run["alpha"], "verified" if ok else why, run["time_s"])
        if best is None or _rank(ok, zf[N.ia], res) > _rank(best[1], best[0][N.ia], best[2]):
            best = (zf, ok, res, why, run)
    zf, ok, res, why, run = best
    return RouteOutcome(ok, float(zf[N.ia]), zf, N, why, runs, time.perf_counter() - t0, run["alpha_raw"], res,
                        run["notes"], run["solver"], run["start"], backend)


def _rank(ok: bool, alpha: float, res: dict | None) -> tuple:
    """Order of the runs' points (the largest is kept): a verified point before any other, the
    lowest alpha among verified ones; among the others the one nearest to a collapse state, the
    lowest complementarity residual (its alpha means little: a run cut short by the budget can
    end near alpha 0 with half its work unaccounted for)."""
    if ok:
        return (1, -float(alpha))
    comp = (res or {}).get("complementarity")
    return (0, -float(comp) if comp is not None and np.isfinite(comp) else -np.inf)


def _vertex_plan(P, N, lp_sol, backend, runs) -> list:
    """The SLA runs (initial penalties 1, 0.1, 0.01) from the LP's simplex vertex
    (:func:`limit.solve.nlp_starts.vertex_start`), for :func:`run` when its own plan verified no
    point and its LP is an interior point; an entry in ``runs`` says why there are none."""
    z0 = nlp_starts.vertex_start(P, N, lp_sol, backend)
    if z0 is None:
        runs.append({"start": "lp-vertex", "solver": "sla", "verified": False,
                     "reason": "no simplex vertex of the LP with a non-associative mechanism"})
        return []
    return [("lp-vertex", z0, "sla", r, None) for r in (1.0, 0.1, 0.01)]


def _coarse_plan(P, N, solver, backend, seed, strategies, hard, runs) -> list:
    """The runs from the coarser friction polygon (:func:`limit.solve.nlp_starts.coarse_slide_faces`),
    for :func:`run` when its own plan verified no point: step 2 of the coarse model (every
    strategy but this one, within what is left of ``hard``), its point transferred to N
    (:func:`limit.solve.nlp_starts.transfer`) and the SLA run from there. With many sliding faces
    the successive LP ends at more stationary points that are not complementary; a point of the
    8 faces inside them has actions that, with the mechanism re-solved for the 24 faces, start
    the SLA from a statically admissible state of the finer model (tests/test_step2_domes.py,
    a dome of 3 rings of 12 voussoirs and a cap). Each run is listed in ``runs`` (the coarse
    model's step 2 as one entry)."""
    n_c = nlp_starts.coarse_slide_faces(P)
    t0 = time.perf_counter()
    from limit.solve.checked_lp import solve_lp

    Pc = nlp_starts.coarse_model(P, n_c)
    lp_c, _, _ = solve_lp(Pc)
    label = f"coarse-{n_c}"
    if lp_c.status != Status.OPTIMAL:
        runs.append({"start": label, "solver": "coarse", "verified": False,
                     "reason": f"the LP with {n_c} sliding faces is {lp_c.status}"})
        return []
    budget = None if hard is None else max(hard - time.perf_counter(), 1.0) / settings.of(P).hard_factor
    out = run(Pc, lp_c, solver="auto", backend="auto", seed=seed,  # chosen by the coarse model's size
              strategies=tuple(s for s in strategies if s != "coarse"), time_budget=budget)
    entry = {"start": label, "solver": "coarse", "alpha": out.alpha, "verified": out.ok,
             "reason": out.reason, "time_s": time.perf_counter() - t0}
    runs.append(entry)
    if not out.ok:
        return []
    z0 = nlp_starts.transfer(N, out.N, out.z, backend)
    if z0 is None:
        entry["reason"] = "its point has no mechanism with this model's faces"
        return []
    return [(label, z0, "sla", r, None) for r in (1.0, 0.1, 0.01)]


def step2(P, lp_sol, method: str = "auto", solver: str = "auto", backend: str = "auto",
          arbitrary: bool = False, global_check: bool = False, iterative: bool = False,
          global_time_limit: float | str = FROM_SETTINGS, time_budget: float | None | str = FROM_SETTINGS,
          dem_state: dict | None = None) -> StepResult:
    """Step 2: the ``nlp`` part of the result file (docs/formats.md, 'Result file').

    ``method`` "auto" skips the NLP where the LP's mechanism has no sliding or twisting
    (:func:`limit.solve.nlp.needs_nlp`) and the LP's point passes the frictional check
    (:func:`limit.solve.nlp.check`, its residuals under "verification"): that point is then a
    frictional collapse state and is the answer. "nlp" always runs it.
    ``solver`` "auto": the large-scale route (:mod:`limit.solve.step2_large`) from the setting
    ``large_min_free`` free blocks on or where the LP is unbounded; below, the large route (with
    ``also_iterative``) and then the successive LP (:func:`run`); the large route's verified alpha
    is kept where lower (:func:`prefer_large`).
    ``arbitrary`` also runs plain SQP from an arbitrary start and records that alpha (paper Fig. 4).
    ``global_check`` adds the mixed-integer global minimum (:mod:`limit.solve.milp`) for scenes of up
    to ``global_max_blocks`` free blocks, within ``global_time_limit`` s ("settings": the
    setting's); ``iterative`` the iterative LP of Gilbert et al.
    (:mod:`limit.solve.iterative_lp`). ``time_budget``: see :func:`run`. ``dem_state``
    ({"displacement": {block id: motion}, "source": "yade"|...}): a dynamic run's collapse state,
    tried as a start by :func:`adopt_dem_state` after the rest. The status is "infeasible" where
    the LP's is, or where the answer's alpha is below zero (:func:`_settled`).
    """
    t0 = time.perf_counter()
    st = settings.of(P)
    if time_budget == FROM_SETTINGS:
        time_budget = st.nlp_time_budget
    if global_time_limit == FROM_SETTINGS:
        global_time_limit = st.global_time_limit
    if lp_sol.status not in (Status.OPTIMAL, Status.UNBOUNDED):
        status = Status.INFEASIBLE if lp_sol.status == Status.INFEASIBLE else Status.SKIPPED
        return StepResult(status, None, 0.0, f"the LP (step 1) is {lp_sol.status}: no start for step 2")
    n_free = P.n_dof // P.scene.ndof
    if lp_sol.status == Status.UNBOUNDED:
        need, why = True, "the LP has no mechanism (sliding needs dilatancy): step 2 starts from the dead load"
    else:
        need, why = nlp.needs_nlp(P, lp_sol)
    large = lp_sol.status == Status.UNBOUNDED or (solver == "auto" and n_free >= st.large_min_free)
    checked = None
    if method == "auto" and not need:  # the LP's point, checked as a frictional collapse state
        N = build(P)
        ok, checked, fail = nlp.check(N, nlp_starts.lp_start(N, lp_sol), lp_sol.alpha)
        if not ok:
            need, why = True, f"the LP's point fails the frictional check ({fail})"
    if method == "auto" and not need:
        part = StepResult(Status.SKIPPED, lp_sol.alpha, time.perf_counter() - t0, why,
                          mechanism.per_block(P, lp_sol.u), {"verification": checked})
        part = _independent(P, lp_sol, part, lp_sol.alpha, global_check, iterative, global_time_limit)
        if dem_state is not None:
            part, _ = adopt_dem_state(P, lp_sol, part, dem_state)
        return _settled(P, part, t0)
    small = not large  # the successive LP's route (an arbitrary start is run below only there)
    if large:  # without a verified point the route goes on, as the successive LP does (run)
        out = _large(P, lp_sol, time_budget, None if time_budget is None else st.hard_factor * time_budget)
    else:  # the large route first: with its point verified, the successive LP keeps to the budget
        alt = _large(P, lp_sol, time_budget) if solver == "auto" and st.also_iterative else None
        out = run(P, lp_sol, solver=solver, start="lp", backend=backend, time_budget=time_budget,
                  verified_elsewhere=alt is not None and alt.ok)
        if alt is not None:
            if prefer_large(out.alpha if out.ok else None, alt.alpha if alt.ok else None, st.lower_by):
                large, out = True, alt.replace(runs=out.runs + alt.runs)
            else:
                out = out.replace(runs=out.runs + alt.runs)
    details = {"solver": out.solver, "start": out.start or "lp", "route": "iterative-lp" if large else "successive-lp"}
    if large:
        details.update(alpha_best=out.alpha_best, alpha_worst=out.alpha_worst, n_verified=out.n_verified,
                       workers=out.workers, n_starts=len(out.starts))
    if not out.ok and out.alpha is not None:
        details["alpha_rejected"] = out.alpha
    if out.residuals is not None:
        details.update(verification=out.residuals, alpha_before_polish=out.alpha_raw, notes=out.notes)
    details["runs"] = out.runs
    point = _point_part(P, out.N, out.z) if out.ok else {}
    part = StepResult(Status.OPTIMAL if out.ok else Status.FAILED, out.alpha if out.ok else None,
                      time.perf_counter() - t0, "" if out.ok else out.reason, point.pop("mechanism", None),
                      {**details, **point})
    if arbitrary and small:
        arb = run(P, lp_sol, solver=solver, start="arbitrary", backend=backend, restarts=False)
        part = part.updated(alpha_arbitrary_start=arb.alpha if arb.ok else None,
                            arbitrary_start_status="optimal" if arb.ok else f"failed: {arb.reason}")
    part = _independent(P, lp_sol, part, part.alpha if out.ok else lp_sol.alpha, global_check, iterative,
                        global_time_limit)
    if dem_state is not None:
        part, _ = adopt_dem_state(P, lp_sol, part, dem_state)
    return _settled(P, part, t0)


def _settled(P, part: StepResult, t0: float) -> StepResult:
    """The finished part (a new one): its ``time_s`` since ``t0``, the independent routes
    included, and status "infeasible" where its verified alpha is below zero by more than the
    setting ``tol_gap``: the dead load alone collapses the assembly (as the LP's rule,
    :func:`limit.solve.checked_lp.solve_lp`)."""
    part = part.updated(time_s=time.perf_counter() - t0)
    if part.status == Status.OPTIMAL and part.alpha is not None and part.alpha < -settings.of(P).tol_gap:
        part = part.updated(status=Status.INFEASIBLE)
    return part


def adopt_dem_state(P, lp_sol, part, dem_state: dict) -> tuple[StepResult, dict]:
    """Step 2 from a dynamic run's collapse state (:func:`limit.solve.dem_start.solve`): (the part
    with the ``dem_start`` entry, the entry); ``part`` (a :class:`StepResult` or a result file's
    ``nlp`` dict) itself unchanged. The entry's verified point
    becomes the answer where it is lower than the part's alpha by more than the setting
    ``lower_by`` (or the part has none); ``alpha_step2`` keeps the alpha it replaces."""
    from limit.solve import dem_start

    part = StepResult.from_dict(part)
    source = dem_state.get("source") or "dem"
    r = dem_start.solve(P, lp_sol, dem_state.get("displacement") or {}, forces=dem_state.get("forces"))
    own = part.alpha if part.status in ANSWERED else None
    adopt = r["status"] == Status.OPTIMAL and lower(r["alpha"], own, settings.of(P).lower_by)
    reason = (f"verified, not below step 2's {own:.6g}" if r["status"] == Status.OPTIMAL and not adopt
              else r["reason"])
    entry = {"source": source, "status": r["status"], "alpha": r["alpha"], "tau": r["tau"],
             "n_flowing": r["n_flowing"], "misfit": r["misfit"], "tried": r["tried"], "time_s": r["time_s"],
             "reason": reason, "adopted": adopt}
    if dem_state.get("alpha") is not None:
        entry["dem_alpha"] = dem_state["alpha"]
    if not adopt:
        return part.updated(dem_start=entry), entry
    if r["tau"] is None:  # from the run's contact forces
        solver, how = "iterative-lp", f"the {source} run's contact forces at its highest equilibrium"
    else:
        solver = "piece-lp"
        how = (f"the {source} run's collapse state (flowing faces: multipliers above {r['tau']:g} of the "
               f"largest, {r['n_flowing']})")
    return _answer(part, {"dem_start": entry}, _point_part(P, r["N"], r["z"]), status=Status.OPTIMAL,
                   alpha=r["alpha"], alpha_step2=own, route="dem-start", solver=solver,
                   verification=r["residuals"],
                   reason=(f"{how} gave a verified point below step 2's "
                           + (f"{own:.6g}" if own is not None else "failure"))), entry


def prefer_large(alpha_successive: float | None, alpha_large: float | None,
                 by: float = settings.DEFAULT.lower_by) -> bool:
    """Whether solver "auto" below the setting ``large_min_free`` (with ``also_iterative``) keeps
    the large route's verified alpha over the successive LP's (None: that route did not verify):
    only when lower by more than ``by`` (relative; the setting ``lower_by``), or when the
    successive LP failed. On the 70-stone Fig. 3 wall the successive LP kept the LP's own point,
    0.570752, where the iterative LP from 0.5 mu verified 0.520808 (YADE 0.4995; LMGC90 0.5123
    searching from 0.5708, 0.5039 from 0.5208)."""
    return lower(alpha_large, alpha_successive, by)


def lower(candidate: float | None, current: float | None, by: float = settings.DEFAULT.lower_by) -> bool:
    """Whether a verified ``candidate`` alpha replaces the ``current`` one (None: none): it exists
    and is lower by more than ``by`` (relative; the setting ``lower_by``), or there is no current one."""
    if candidate is None:
        return False
    return current is None or candidate < current - by * abs(current)


def _large(P, lp_sol, time_budget, hard_budget=None) -> RouteOutcome:
    """The large-scale route's outcome with :func:`run`'s runs and notes (``hard_budget``: see
    :func:`limit.solve.step2_large.solve`)."""
    out = step2_large.solve(P, lp_sol, time_budget=time_budget, hard_budget=hard_budget)
    runs = [dict(r, solver="iterative-lp") for r in out.starts]
    return out.replace(solver="iterative-lp", runs=runs, alpha_raw=out.alpha,
                       notes=[f"iterative LP (ipm) from {len(runs)} start(s), snapped by the piece LP"])


def _point_part(P, N, z) -> dict:
    """The mechanism, interface states and counts of a verified frictional point z (scaled, of N)."""
    _, x, u, lam = N.unscale(z)
    cls = mechanism.classify(P, u)
    out = {"mechanism": mechanism.per_block(P, u), "normalisation": "unit work of the live load: fL . u = 1",
           "interfaces": interfaces_part(P, P.model.H @ x, cls), "counts": {k: int(v.sum()) for k, v in cls.items()}}
    if P.scene.ties:
        out["ties"] = ties_part(P, x, u)
    return out


def _answer(part: StepResult, *updates: dict, **fields) -> StepResult:
    """A new part whose answer is another verified point: ``part`` updated by each of ``updates``
    and then ``fields`` (in this order), without the ``alpha_rejected`` of a failed search."""
    merged = {}
    for u in (*updates, fields):
        merged.update(u)
    return part.updated(**merged).without("alpha_rejected")


def _adopt_global(P, lp_sol, part: StepResult, g: milp.GlobalMinimum, entry) -> tuple[StepResult, dict]:
    """(part, entry): the MILP's point made step 2's answer where it is lower than step 2's alpha
    by more than the setting ``lower_by`` (relative; or step 2 has none) and passes the same
    independent check (:func:`limit.solve.nlp.finish`: the piece-LP polish, then
    :func:`limit.solve.nlp.check`), and the MILP's ``entry`` with "adopted" (and why not); new
    dicts, the arguments unchanged. A MILP point is a frictional collapse state like step 2's; an
    incumbent at the time limit (no proof) counts too. ``alpha_step2`` keeps the local search's
    alpha."""
    a, own, by = g.alpha, part.alpha, settings.of(P).lower_by
    if g.z is None or not lower(a, own, by):
        return part, entry
    N = build(P)
    z, ok, res, why, note = nlp.finish(N, g.z, lp_sol.alpha, "highs")
    if not ok or not lower(float(z[N.ia]), own, by):
        return part, {**entry, "adopted": False,
                      "reason": "; ".join(t for t in (entry.get("reason"), f"its point fails the check: {why}"
                                                      if not ok else "below step 2's alpha only before the polish")
                                          if t)}
    return _answer(part, _point_part(P, N, z), status=Status.OPTIMAL, alpha=float(z[N.ia]), alpha_step2=own,
                   route="global-milp", solver="milp", verification=res,
                   reason=(f"the global MILP's point ({g.status}; {note}) passed the check below step 2's "
                           + (f"{own:.6g}" if own is not None else "failure"))), {**entry, "adopted": True}


def _independent(P, lp_sol, part: StepResult, alpha_ub, global_check, iterative, time_limit) -> StepResult:
    """The part with the independent routes (global MILP, iterative LP) added: a new part, ``part``
    unchanged. A MILP point below step 2's alpha that passes the check becomes the answer
    (:func:`_adopt_global`)."""
    n_free, most = P.n_dof // P.scene.ndof, settings.of(P).global_max_blocks
    if global_check:
        if n_free > most:
            part = part.updated(**{"global": {"status": Status.SKIPPED, "reason": f"{n_free} free blocks > {most}"}})
        elif alpha_ub is None:  # the LP unbounded and step 2 without a point: no bound for the MILP
            part = part.updated(**{"global": {"status": Status.SKIPPED, "reason": "no known alpha to bound the MILP"}})
        else:
            g = milp.global_minimum(P, alpha_ub, time_limit=time_limit)
            entry = g.entry()
            if g.alpha is not None and part.alpha is not None:
                entry["gap"] = (part.alpha - g.alpha) / max(abs(g.alpha), 1e-12)
            part, entry = _adopt_global(P, lp_sol, part, g, entry)
            part = part.updated(**{"global": entry})
    if iterative and lp_sol.status != Status.OPTIMAL:
        part = part.updated(iterative_lp={"status": Status.SKIPPED, "alpha": None,
                                          "reason": f"the LP is {lp_sol.status}"})
    elif iterative:
        it = iterative_lp.solve(P, lp_sol)
        part = part.updated(iterative_lp=it.entry())
    return part
