"""Tie design: the least total tie capacity, over candidate ties, at which a scene's frictional
collapse multiplier reaches a target alpha A (``limit design``).

1. **The LP** (the static theorem of the associative problem): with alpha held at A, find
   interface actions x and tie tensions T in equilibrium, ``E x + f0 + A fL = 0``, inside the
   joints' yield domain, ``0 <= T_j <= C_j``, and minimise ``sum C_j`` (N). Any such stress field
   is a lower bound of the associative collapse: with capacities C the LP's alpha is at least
   A, and no smaller total does it. Candidates that get C_j = 0 are not needed.
2. **Step 2 checks it.** The frictional alpha can lie below the LP's (friction does not dilate),
   so the design is analysed in full (:func:`limit.analysis.analyse`); every capacity is scaled
   by one common factor, the least at which the frictional alpha reaches A: bracketed by
   doubling from 1 (or halving, where the LP's capacities already pass), then bisected
   (:data:`RTOL`). Each trial is a full analysis.
3. **Where the LP needs no tie but step 2 falls short** (the associative LP can be held up by
   dilatancy that a frictional joint does not have, e.g. a facade that rocks away from a cross
   wall whose joint with it would have to open as it slides), the LP is asked instead for the
   target ``alpha_LP0 A / alpha_2`` (the untied LP's alpha raised by the gain that the frictional
   alpha alpha_2 needs), and step 2 then scales its ties as in 2.

Candidates are tie entries of the scene format (``limit.model.ties``) whose ``capacity`` is an
upper bound when given (none: unbounded).
"""
from __future__ import annotations

import copy
import time

import numpy as np

from limit.solve.status import ANSWERED, CheckStatus, Status

#: relative width of the bisection on the capacities' common factor (step 2's check)
RTOL = 1e-3
#: doublings of the common factor before the design is given up as out of reach
MAX_DOUBLINGS = 8
#: a candidate's capacity below this fraction of the largest is dropped (not needed)
DROP = 1e-6


def _with(data: dict, ties: list) -> dict:
    out = copy.deepcopy(data)
    out["ties"] = ties
    return out


def least_capacity(data: dict, candidates: list, target: float, keep: list = ()) -> dict:
    """Step 1 of the module docstring: {"status" ("optimal", "infeasible": no design reaches A with
    these candidates, or another LP status), "capacities" (N, per candidate), "total" (N)}.
    ``keep``: ties of the scene that stay as they are (not candidates)."""
    import scipy.sparse as sp

    from limit.model.assemble import assemble
    from limit.model.scene import load_scene
    from limit.solve import lpsub

    scene = load_scene(_with(data, list(keep) + [{**c, "capacity": 1.0} for c in candidates]))
    P = assemble(scene)
    nt = len(candidates)
    wc = P.Wc
    nx, nf = P.model.n_x, P.model.n_faces
    cap_rows = nf - 2 * nt + 2 * np.arange(nt) + 1  # each tie's "T <= capacity" row (limit.model.yield_domain.with_ties)
    # unknowns [xh (nx), c (nt)] with C_j = wc c_j; the tie rows' capacity moves to the left-hand side
    Yc = sp.csr_matrix((-wc / P.Sy[cap_rows], (cap_rows, np.arange(nt))), shape=(nf, nt))
    Aub = sp.hstack([P.Yh, Yc]).tocsr()
    bub = P.kh.copy()
    bub[cap_rows] = 0.0
    Aeq = sp.hstack([P.Eh, sp.csr_matrix((P.Eh.shape[0], nt))]).tocsr()
    beq = -P.f0h - target * P.fLh
    cost = np.concatenate([np.zeros(nx), np.ones(nt)])
    lo = np.concatenate([np.full(nx, -np.inf), np.zeros(nt)])
    bound = [c.get("capacity") for c in candidates]
    hi = np.concatenate([np.full(nx, np.inf), [np.inf if b is None else float(b) / wc for b in bound]])
    res = lpsub.solve(cost, Aeq, beq, Aub, bub, lo, hi, "highs")
    if not res.ok:
        return {"status": Status.INFEASIBLE if res.no_point else Status.FAILED, "capacities": None, "total": None,
                "reason": res.status}
    C = wc * res.z[nx:]
    C[C < DROP * max(float(C.max(initial=0.0)), 1e-300)] = 0.0
    return {"status": Status.OPTIMAL, "capacities": C.tolist(), "total": float(C.sum()), "reason": ""}


def _analyser(changes: dict | None):
    """:func:`limit.analysis.analyse` with the settings ``changes`` ({name: value}) in its options."""
    import functools

    from limit.analysis import analyse
    from limit.model.assemble import Options

    return functools.partial(analyse, options=Options(settings=dict(changes or {})))


def _frictional(res: dict, method: str):
    """The frictional alpha of an analysis (step 2's; the LP's under ``method`` "lp"), or None."""
    step = res.get("nlp") or {}
    a = step.get("alpha") if step.get("status") in ANSWERED else None
    if a is None and method == "lp":
        a = res["lp"].get("alpha")
    return a


def design(data: dict, candidates: list, target: float, method: str = "auto", progress=None,
           keep: list = (), settings: dict | None = None) -> dict:
    """The design of the module docstring: {"status" ("done", "infeasible", "out_of_reach",
    "failed"), "target", "lp_capacities" (step 1's, N), "factor" (step 2's common factor),
    "ties" (the designed tie entries, capacity in N, the unneeded dropped), "result" (the
    result dict of the designed scene's analysis), "trials" [(factor, frictional alpha)], "reason",
    "time_s"}. ``data``: the scene dict in its own units, as the candidates' points; ``keep``: the
    scene's ties that stay as they are; ``progress(text)``: told of each trial; ``settings``: the
    settings to change ({name: value}, :mod:`limit.settings`) in every trial's analysis."""
    from limit.model.scene import load_scene

    analyse = _analyser(settings)

    t0 = time.perf_counter()
    if not candidates:
        raise ValueError("no candidate ties: give --candidates FILE or the scene's own 'ties'")
    if not target > 0:
        raise ValueError(f"--target-alpha: must be > 0, got {target}")
    out = {"target": target, "lp_capacities": None, "factor": None, "ties": [], "result": None,
           "trials": [], "reason": "", "time_s": None, "lp_target": target}
    lp = least_capacity(data, candidates, target, keep)
    if lp["status"] == Status.OPTIMAL and not any(c > 0 for c in lp["capacities"]):
        # the LP reaches the target untied; step 2 may not (friction does not dilate)
        res = analyse(load_scene(_with(data, list(keep))), method=method).data
        a = _frictional(res, method)
        out["trials"].append((0.0, a))
        if a is not None and a >= target * (1 - 1e-9):
            out.update(status=CheckStatus.DONE, factor=1.0, result=res, lp_capacities=lp["capacities"],
                       time_s=time.perf_counter() - t0)
            return out
        lp_alpha = res["lp"].get("alpha")
        if a is None or a <= 0 or lp_alpha is None:
            out.update(status=CheckStatus.FAILED, reason=f"the untied scene has no frictional alpha to raise ({a})",
                       time_s=time.perf_counter() - t0)
            return out
        # the LP's target raised by the gain the frictional alpha needs (the module docstring, 3.)
        out["lp_target"] = lp_alpha * target / a
        if progress:
            progress(f"the LP reaches {target:g} untied, step 2 only {a:.6g}: LP target {out['lp_target']:.6g}")
        lp = least_capacity(data, candidates, out["lp_target"], keep)
    out["lp_capacities"] = lp["capacities"]
    if lp["status"] != Status.OPTIMAL:
        out.update(status=lp["status"], reason=("no capacities of these candidate ties reach the target: the "
                                                 "associative LP has no admissible state at alpha = "
                                                 f"{out['lp_target']:g}" if lp["status"] == Status.INFEASIBLE else lp["reason"]),
                   time_s=time.perf_counter() - t0)
        return out
    if progress:
        progress("LP: least total capacity " + ", ".join(f"{c.get('id', f'tie-{k}')} {v:.6g} N" for k, (c, v)
                                                         in enumerate(zip(candidates, lp["capacities"])) if v > 0))
    base = [dict(c, capacity=cap) for c, cap in zip(candidates, lp["capacities"]) if cap > 0]
    bound = [c.get("capacity") for c, cap in zip(candidates, lp["capacities"]) if cap > 0]

    def trial(f):
        ties = [dict(c, capacity=min(c["capacity"] * f, b) if b is not None else c["capacity"] * f)
                for c, b in zip(base, bound)]
        res = analyse(load_scene(_with(data, list(keep) + ties)), method=method).data
        a = _frictional(res, method)
        out["trials"].append((f, a))
        if progress:
            progress(f"factor {f:.4g}: frictional alpha {a if a is None else round(a, 6)}")
        return ties, res, (a is not None and a >= target * (1 - 1e-9))

    # the least common factor at which step 2 reaches the target: bracketed by doubling (or
    # halving, where the LP's capacities already suffice), then bisected
    ties, res, ok = trial(1.0)
    lo, hi, best = (None, 1.0, (ties, res)) if ok else (1.0, None, None)
    for _ in range(MAX_DOUBLINGS):
        if lo is not None and hi is not None:
            break
        f = hi / 2.0 if hi is not None else lo * 2.0
        ties, res, ok = trial(f)
        if ok:
            hi, best = f, (ties, res)
        else:
            lo = f
    if hi is None:
        out.update(status=CheckStatus.OUT_OF_REACH, reason=f"step 2 stays below {target:g} with every capacity "
                   f"{lo:g} times the LP's", time_s=time.perf_counter() - t0)
        return out
    lo = lo if lo is not None else 0.0
    while hi - lo > RTOL * hi:
        mid = 0.5 * (lo + hi)
        ties, res, ok = trial(mid)
        if ok:
            hi, best = mid, (ties, res)
        else:
            lo = mid
    f_ok = hi
    out.update(status=CheckStatus.DONE, factor=f_ok, ties=best[0], result=best[1], time_s=time.perf_counter() - t0)
    return out


#: rounds of the design for a code check (each a full design) before it is given up
DEMAND_ROUNDS = 5


def _linear_ratio(res: dict):
    """(alpha, ratio) of an analysis with a verdict: the frictional (else the LP's) alpha of the
    checked mechanism and the least capacity/demand ratio of its linear checks (SLV, and SLD where
    the demand has one); (alpha, None) where the verdict has no check."""
    v = res.get("verdict") or {}
    c = v.get("check") or {}
    ratios = [c[k]["ratio"] for k in ("linear", "damage") if c.get(k)]
    return v.get("alpha0"), (min(ratios) if ratios else None)


def design_for_demand(data: dict, candidates: list, method: str = "auto", progress=None, keep: list = (),
                      settings: dict | None = None) -> dict:
    """The design whose target is the code check of the scene's ``demand`` (NTC 2018, C8.7.1):
    the alpha at which its linear checks pass. The checked acceleration a0* = alpha0 g / (e* FC)
    is proportional to alpha0 for a given mechanism, so the target is alpha0 / ratio; ties change
    the mechanism and with it e*, so the design is repeated with the new ratio (each round's target
    at least the last one's) until the check passes, at most :data:`DEMAND_ROUNDS` times.
    Returns :func:`design`'s record with "rounds" [(target, alpha0, ratio)] and "check" (the
    designed scene's verdict check); status "done" only when that check passes. ``settings``: as
    for :func:`design`."""
    from limit.model.scene import load_scene

    analyse = _analyser(settings)

    t0 = time.perf_counter()
    scene = load_scene(_with(data, list(keep)))
    if scene.demand is None:
        raise ValueError("no --target-alpha and no 'demand' in the scene: give one of the two")
    res = analyse(scene, method=method).data
    alpha, ratio = _linear_ratio(res)
    if ratio is None:
        raise ValueError(f"the scene's code check did not run: {(res.get('verdict') or {}).get('reason', 'no check')}")
    rounds = [(None, alpha, ratio)]
    if progress:
        progress(f"without new ties: alpha {alpha:.6g}, linear check ratio {ratio:.4g}")
    if ratio >= 1.0:
        return {"status": CheckStatus.DONE, "target": alpha, "lp_capacities": None, "factor": 1.0, "ties": [], "result": res,
                "trials": [], "reason": "the check passes without ties", "rounds": rounds,
                "check": res["verdict"]["check"], "time_s": time.perf_counter() - t0}
    target = 0.0
    for _ in range(DEMAND_ROUNDS):
        target = max(target * (1 + RTOL), alpha / ratio)
        if progress:
            progress(f"target alpha {target:.6g} (alpha {alpha:.6g} / ratio {ratio:.4g})")
        out = design(data, candidates, target, method=method, progress=progress, keep=keep, settings=settings)
        if out["status"] != CheckStatus.DONE:
            out.update(rounds=rounds, check=None, time_s=time.perf_counter() - t0)
            return out
        alpha, ratio = _linear_ratio(out["result"])
        rounds.append((target, alpha, ratio))
        if ratio is None or ratio >= 1.0:
            break
    out.update(rounds=rounds, check=(out["result"].get("verdict") or {}).get("check"), time_s=time.perf_counter() - t0)
    if ratio is None or ratio < 1.0:
        out.update(status=CheckStatus.OUT_OF_REACH, reason=f"the check's ratio is {ratio} after {len(rounds) - 1} rounds of design")
    return out
