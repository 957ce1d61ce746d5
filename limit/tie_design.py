"""Tie design: the least total tie capacity, over candidate ties, at which a scene's frictional
collapse multiplier reaches a target alpha A (``limit design``).

1. **The LP** (the static theorem of the associative problem): with alpha held at A, find
   interface actions x and tie tensions T in equilibrium, ``E x + f0 + A fL = 0``, inside the
   joints' yield domain, ``0 <= T_j <= C_j``, and minimise ``sum C_j`` (N). Any such stress field
   is a lower bound of the associative collapse: with capacities C the LP's alpha is at least
   A, and no smaller total does it. Candidates that get C_j = 0 are not needed.
2. **Step 2 checks it.** The frictional alpha can lie below the LP's (friction does not dilate),
   so the design is analysed in full (:func:`limit.analysis.analyse`); while the frictional
   alpha stays below A every capacity is raised by the same factor, first doubling and then
   bisecting (:data:`RTOL`), until it reaches A. Each trial is a full analysis.

Candidates are tie entries of the scene format (``limit.model.ties``) whose ``capacity`` is an
upper bound when given (none: unbounded).
"""
from __future__ import annotations

import copy
import time

import numpy as np

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
        return {"status": "infeasible" if res.no_point else "failed", "capacities": None, "total": None,
                "reason": res.status}
    C = wc * res.z[nx:]
    C[C < DROP * max(float(C.max(initial=0.0)), 1e-300)] = 0.0
    return {"status": "optimal", "capacities": C.tolist(), "total": float(C.sum()), "reason": ""}


def design(data: dict, candidates: list, target: float, method: str = "auto", progress=None,
           keep: list = ()) -> dict:
    """The design of the module docstring: {"status" ("done", "infeasible", "out_of_reach",
    "failed"), "target", "lp_capacities" (step 1's, N), "factor" (step 2's common factor),
    "ties" (the designed tie entries, capacity in N, the unneeded dropped), "result" (the
    analysis of the designed scene), "trials" [(factor, frictional alpha)], "reason",
    "time_s"}. ``data``: the scene dict in its own units, as the candidates' points; ``keep``: the
    scene's ties that stay as they are; ``progress(text)``: told of each trial."""
    from limit.analysis import analyse
    from limit.model.scene import load_scene

    t0 = time.perf_counter()
    if not candidates:
        raise ValueError("no candidate ties: give --candidates FILE or the scene's own 'ties'")
    if not target > 0:
        raise ValueError(f"--target-alpha: must be > 0, got {target}")
    lp = least_capacity(data, candidates, target, keep)
    out = {"target": target, "lp_capacities": lp["capacities"], "factor": None, "ties": [], "result": None,
           "trials": [], "reason": "", "time_s": None}
    if lp["status"] != "optimal":
        out.update(status=lp["status"], reason=("no capacities of these candidate ties reach the target: the "
                                                 "associative LP has no admissible state at alpha = "
                                                 f"{target:g}" if lp["status"] == "infeasible" else lp["reason"]),
                   time_s=time.perf_counter() - t0)
        return out
    if progress:
        progress("LP: least total capacity " + ", ".join(f"{c.get('id', f'tie-{k}')} {v:.6g} N" for k, (c, v)
                                                         in enumerate(zip(candidates, lp["capacities"]))))
    base = [dict(c, capacity=cap) for c, cap in zip(candidates, lp["capacities"]) if cap > 0]
    bound = [c.get("capacity") for c, cap in zip(candidates, lp["capacities"]) if cap > 0]

    def trial(f):
        ties = [dict(c, capacity=min(c["capacity"] * f, b) if b is not None else c["capacity"] * f)
                for c, b in zip(base, bound)]
        res = analyse(load_scene(_with(data, list(keep) + ties)), method=method)
        step = res.get("nlp") or {}
        a = step.get("alpha") if step.get("status") in ("optimal", "skipped") else None
        if a is None and method == "lp":
            a = res["lp"].get("alpha")
        out["trials"].append((f, a))
        if progress:
            progress(f"factor {f:.4g}: frictional alpha {a if a is None else round(a, 6)}")
        return ties, res, a

    if not base:  # the scene reaches the target without ties
        res = analyse(load_scene(_with(data, list(keep))), method=method)
        out.update(status="done", factor=1.0, result=res, time_s=time.perf_counter() - t0)
        return out
    f_ok, best = None, None
    ties, res, a = trial(1.0)
    if a is not None and a >= target * (1 - 1e-9):
        f_ok, best = 1.0, (ties, res)
    else:
        lo, f = 1.0, 1.0
        for _ in range(MAX_DOUBLINGS):
            f *= 2.0
            ties, res, a = trial(f)
            if a is not None and a >= target * (1 - 1e-9):
                f_ok, best = f, (ties, res)
                break
            lo = f
        if f_ok is None:
            out.update(status="out_of_reach", reason=f"step 2 stays below {target:g} with every capacity "
                       f"{f:g} times the LP's", time_s=time.perf_counter() - t0)
            return out
        hi = f_ok
        while hi - lo > RTOL * hi:
            mid = 0.5 * (lo + hi)
            ties, res, a = trial(mid)
            if a is not None and a >= target * (1 - 1e-9):
                hi, best = mid, (ties, res)
            else:
                lo = mid
        f_ok = hi
    out.update(status="done", factor=f_ok, ties=best[0], result=best[1], time_s=time.perf_counter() - t0)
    return out
