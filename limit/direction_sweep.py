"""The worst horizontal direction of the live load of a 3D scene: alpha(theta) from the
associative LP over a sweep of directions, and the frictional step 2 at the minimum (or, with
``every``, at every direction: the frictional worst direction).

theta (degrees) is measured in the horizontal plane (normal to gravity) from the scene's
own live direction, counter-clockwise seen from above; the live load must be body forces
(each one's direction is turned about the vertical by theta, keeping its vertical part).
The directions run in parallel on Dask workers (:func:`limit.dask_pool.dask_client`: a
local cluster of ``jobs`` processes, or the scheduler at ``scheduler``, as the catalog's
validation does) when that pays: the first two directions are solved in this process, the
second timed, and a local cluster is started only if the time saved exceeds
:data:`DASK_START_S`. With ``mirror`` (the scene is mirror-
symmetric about the vertical plane containing its live direction, :mod:`limit.verdict.symmetry`,
declared by the scene's ``"symmetry": "mirror"`` or asked for), alpha(-theta) =
alpha(theta): only 0..180 degrees are solved and the rest is mirrored.
"""
from __future__ import annotations

import math
import os
import time

import numpy as np

from limit.model.turned_load import turned as _turn
from limit.solve.status import ANSWERED, Status

#: wall-clock cost of starting a local Dask cluster (s, measured 2-3 s on 2 cores): the sweep
#: goes parallel only when the time it saves exceeds this (Fig. 6: 72 LPs of 30 ms took 2.6 s
#: in one process, 3.3 s on two Dask workers)
DASK_START_S = 2.5
#: a frictional sweep's second pass: each direction tries the collapse states of its two
#: neighbours and of the lowest direction as starts, for at most this many rounds (a round
#: revisits only the neighbours of directions that went lower)
NEIGHBOUR_ROUNDS = 3
#: wall-clock budget (s) of the successive LPs of one start, where its piece LP does not verify
NEIGHBOUR_SLA_BUDGET = 10.0


def _azimuth(data: dict) -> float | None:
    """Azimuth (degrees, counter-clockwise from +x seen from above) of the first live body
    force's horizontal part, for gravity along -z; None for another gravity or no horizontal part."""
    g = np.asarray(data.get("gravity", [0.0, 0.0, -9.81]), dtype=float)
    live = data["loads"]["live"]
    if not (g[0] == 0.0 and g[1] == 0.0 and g[2] < 0.0) or not live:
        return None
    d = np.asarray(live[0]["direction"], dtype=float)
    return math.degrees(math.atan2(d[1], d[0])) % 360.0 if math.hypot(d[0], d[1]) > 0 else None


def format_direction(d, digits: int = 3) -> str:
    """A direction vector as "(x, y, z)" for text and legends."""
    return "(" + ", ".join(f"{c:.{digits}f}" for c in d) + ")"


def _lp_alpha(args) -> tuple:
    """(theta, LP status, LP alpha, seconds, step 2's status, step 2's alpha, step 2's mechanism)
    of one direction; step 2 (method "auto": skipped where the LP's mechanism is frictional
    already) only when the third of ``args`` asks for it, else its three entries are None."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.load_checks import NoLiveWork
    from limit.model.scene import load_scene


    data, theta = args[:2]
    frictional = len(args) > 2 and args[2]
    changes = dict(args[3]) if len(args) > 3 and args[3] else {}
    t0 = time.perf_counter()
    try:
        scene = load_scene(_turn(data, theta))
    except NoLiveWork:  # turned onto blocked dofs only: no mechanism in this direction
        return theta, Status.UNBOUNDED, None, time.perf_counter() - t0, None, None, None
    # the neighbour pass turns states between directions instead (direction_starts_deg off), and the
    # sweep solves the reversed direction itself (mirror_starts off)
    res = analyse(scene, method="auto" if frictional else "lp",
                  options=Options(settings={**changes, "direction_starts_deg": 0, "mirror_starts": False}),
                  nlp_options={"global_check": False, "iterative": False, "arbitrary": False} if frictional else None).data
    lp, nlp = res.get("lp") or {}, res.get("nlp") or {}
    if not frictional:
        return theta, lp.get("status"), lp.get("alpha"), time.perf_counter() - t0, None, None, None
    fric = nlp.get("alpha") if nlp.get("status") in ANSWERED else None
    return (theta, lp.get("status"), lp.get("alpha"), time.perf_counter() - t0, nlp.get("status"), fric,
            nlp.get("mechanism") if fric is not None else None)


def _from_starts(args) -> tuple:
    """(theta, the lowest verified frictional alpha from the given mechanisms as starts or None,
    its mechanism, the direction whose mechanism gave it, seconds): step 2 in direction theta from
    the collapse states of other directions (``starts``: [(theta_j, mechanism_j)]), each tried as
    the piece LP's flowing set (:func:`limit.solve.dem_start.solve`, as a dynamic run's state)."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.scene import load_scene
    from limit.solve import dem_start, mechanism

    data, theta, starts = args[:3]
    changes = dict(args[3]) if len(args) > 3 and args[3] else {}
    t0 = time.perf_counter()
    best = (None, None, None)
    try:
        run = analyse(load_scene(_turn(data, theta)), method="lp", options=Options(settings=changes))
    except Exception:  # noqa: BLE001 - a direction that cannot be analysed keeps its first answer
        return theta, None, None, None, time.perf_counter() - t0
    if run.sol.status != Status.OPTIMAL:
        return theta, None, None, None, time.perf_counter() - t0
    for th, mech in starts:
        r = dem_start.solve(run.P, run.sol, mech, time_budget=NEIGHBOUR_SLA_BUDGET)
        if r["status"] == Status.OPTIMAL and (best[0] is None or r["alpha"] < best[0]):
            _, _, u, _ = r["N"].unscale(r["z"])
            best = (float(r["alpha"]), mechanism.per_block(run.P, u), th)
    return theta, best[0], best[1], best[2], time.perf_counter() - t0


def sweep(data: dict, step_deg: float = 5.0, *, mirror: bool | None = None, jobs: int | None = None,
          scheduler: str | None = None, frictional: bool = True, progress=None, every: bool = False,
          settings: dict | None = None) -> dict:
    """alpha(theta) of the scene dict ``data`` (3D) every ``step_deg`` over 360 degrees;
    returns {"theta" (deg), "alpha" (LP, NaN where not optimal), "status", "min_theta",
    "min_alpha" (LP), "min_nlp" (the analysis at the minimum: "lp", "nlp" (step 2 where it
    applies) and "verdict" (the code check there, for a scene with a demand), or None),
    "time_s", "lp_time_s" (summed over directions), "jobs", "mirror", "solved" (directions
    solved), "azimuth0" (degrees: where theta = 0 points, :func:`_azimuth`; None unless gravity is
    along -z), "min_direction" (the first live body force's direction at the minimum, global
    axes)}. ``progress(done, total)`` is called as directions finish. ``mirror`` None: as
    the scene declares (``"symmetry": "mirror"``); a mirror symmetry, declared or asked for,
    is checked first
    (:func:`limit.verdict.symmetry.check_mirror`: ValueError naming a block without its image).

    ``every``: step 2 runs at every direction too, not only at the LP's minimum (the frictional
    alpha can lie anywhere below the LP's, so the LP's worst direction need not be the frictional
    one); the result then also has "alpha_frictional" (NaN where step 2 has no verified point),
    "status_frictional", "min_theta_frictional", "min_alpha_frictional" and "min_frictional" (the
    analysis at the frictional minimum, with the code check there, like "min_nlp"), and
    "neighbour_passes" (:func:`_neighbour_passes`: the directions that went lower from another
    direction's collapse state as a start, with their alpha before and after).

    ``settings``: the settings to change ({name: value}, :mod:`limit.settings`) in every direction's
    analysis (each direction's own direction starts stay off: the neighbour pass does their work)."""
    if data.get("dim") != 3:
        raise ValueError("dim: the direction sweep is for 3D scenes (a 2D scene's load direction is +/- x)")
    if not (0 < step_deg <= 180):
        raise ValueError(f"step_deg must be in (0, 180], got {step_deg!r}")
    t0 = time.perf_counter()
    changes = dict(settings or {})
    if mirror is None:
        mirror = data.get("symmetry") == "mirror"
    if mirror:
        from limit.model.scene import load_scene
        from limit.verdict.symmetry import check_mirror

        check_mirror(load_scene(data))
    n = int(round(360.0 / step_deg))
    thetas = np.arange(n) * (360.0 / n)
    todo = [t for t in thetas if t <= 180.0 + 1e-9] if mirror else list(thetas)
    jobs = max(1, min(jobs or os.cpu_count() or 1, len(todo)))
    got = {}

    mechs = {}

    def record(out):
        th, st, a, dt, fst, fa, mech = out
        got[th] = (st, a, dt, fst, fa)
        mechs[th] = mech
        if progress:
            progress(len(got), len(todo))
        return dt

    for t in todo[:2]:  # in this process: the second times one direction (the first pays the imports)
        dt = record(_lp_alpha((data, float(t), every, changes)))
    rest = todo[2:]
    parallel = bool(scheduler) or (bool(rest) and jobs > 1 and dt * len(rest) * (1.0 - 1.0 / jobs) > DASK_START_S)
    jobs = jobs if parallel else 1
    _map(_lp_alpha, [(data, float(t), every, changes) for t in rest], record, jobs, scheduler, parallel)
    passes = _neighbour_passes(data, todo, got, mechs, jobs, scheduler, parallel, mirror, changes) if every else None
    status, alpha, fstatus, falpha = [], [], [], []
    for t in thetas:
        src = t if t in got else (360.0 - t) % 360.0  # mirrored
        st, a, _, fst, fa = got[src]
        status.append(st)
        alpha.append(a if st == Status.OPTIMAL and a is not None else float("nan"))
        fstatus.append(fst)
        falpha.append(fa if fa is not None else float("nan"))
    alpha = np.array(alpha, dtype=float)
    falpha = np.array(falpha, dtype=float)
    out = {"theta": thetas.tolist(), "alpha": alpha.tolist(), "status": status, "min_theta": None, "min_alpha": None,
           "min_nlp": None, "lp_time_s": sum(v[2] for v in got.values()), "jobs": jobs, "mirror": bool(mirror),
           "solved": len(todo), "azimuth0": _azimuth(data), "min_direction": None}
    if every:
        out.update(alpha_frictional=falpha.tolist(), status_frictional=fstatus, min_theta_frictional=None,
                   min_alpha_frictional=None, min_frictional=None, neighbour_passes=passes)
        if np.isfinite(falpha).any():
            kf = int(np.nanargmin(falpha))
            out.update(min_theta_frictional=float(thetas[kf]), min_alpha_frictional=float(falpha[kf]),
                       min_frictional=_at(data, float(thetas[kf]), _start(float(thetas[kf]), mechs, passes), changes),
                       min_direction_frictional=_turn(data, float(thetas[kf]))["loads"]["live"][0]["direction"])
    if not np.isfinite(alpha).any():
        return {**out, "time_s": time.perf_counter() - t0}
    k = int(np.nanargmin(alpha))
    at_min = _at(data, float(thetas[k]), None, changes) if frictional else None
    return {**out, "min_theta": float(thetas[k]), "min_alpha": float(alpha[k]), "min_nlp": at_min,
            "min_direction": _turn(data, float(thetas[k]))["loads"]["live"][0]["direction"],
            "time_s": time.perf_counter() - t0}


def _map(fn, tasks, record, jobs, scheduler, parallel) -> None:
    """``record(fn(task))`` for every task: on Dask workers when ``parallel``, else here."""
    if parallel and tasks:
        from dask.distributed import as_completed

        from limit.dask_pool import dask_client

        with dask_client(jobs, scheduler) as client:
            for f in as_completed(client.map(fn, tasks, pure=False)):
                record(f.result())
    else:
        for t in tasks:
            record(fn(t))


def _neighbour_passes(data, todo, got, mechs, jobs, scheduler, parallel, mirror, changes=None) -> dict:
    """The frictional sweep's second pass, in place on ``got`` and ``mechs`` (module constants
    NEIGHBOUR_ROUNDS, NEIGHBOUR_SLA_BUDGET). Step 2 in one direction is a local search, and the
    frictional alpha, a minimum over mechanisms of loads that turn continuously, does not jump
    between neighbouring directions where step 2 found the same family of states: a direction
    whose neighbour (or the lowest direction) has a lower verified state tries that state as a
    start, and keeps it where it verifies lower (by more than the setting lower_by). Returns
    {"rounds", "improved": {theta: [alpha before, after, the direction of the start]}, "time_s"}."""
    from limit import settings

    t0 = time.perf_counter()
    by = settings.DEFAULT.replace(changes or {}).lower_by
    order = sorted(todo)
    n = len(order)
    improved, active = {}, set(order)
    rounds = 0

    def fa(t):
        return got[t][4]

    for rounds in range(1, NEIGHBOUR_ROUNDS + 1):
        known = [t for t in order if fa(t) is not None and mechs.get(t)]
        if not known:
            break
        low = min(known, key=fa)
        tasks = []
        for k, t in enumerate(order):
            if t not in active:
                continue
            near = {order[(k - 1) % n], order[(k + 1) % n], low} if not mirror else \
                {order[max(k - 1, 0)], order[min(k + 1, n - 1)], low}
            starts = [(s, mechs[s]) for s in sorted(near) if s != t and s in known and
                      (fa(t) is None or fa(s) < fa(t) - by * abs(fa(t)))]
            if starts:
                tasks.append((data, float(t), starts, changes))
        went_lower = []

        def record(out):
            th, a, mech, src, _ = out
            old = fa(th)
            if a is not None and (old is None or a < old - by * abs(old)):
                st, la, dt, _, _ = got[th]
                got[th] = (st, la, dt, Status.OPTIMAL, a)
                mechs[th] = mech
                first = improved.get(th, [old])[0]
                improved[th] = [first, a, src]
                went_lower.append(th)

        _map(_from_starts, tasks, record, jobs, scheduler, parallel)
        if not went_lower:
            break
        active = {order[(order.index(t) + d) % n] for t in went_lower for d in (-1, 1)}
    return {"rounds": rounds, "improved": {f"{t:g}": v for t, v in sorted(improved.items())},
            "time_s": time.perf_counter() - t0}


def _start(theta, mechs, passes) -> dict | None:
    """The collapse state that a solved direction's answer came from in the neighbour pass, as a
    step 2 start ({"displacement", "source"}), or None where its own step 2 gave it. (The lowest
    of mirrored equal values is the solved one, the first.)"""
    hit = (passes or {}).get("improved", {}).get(f"{theta:g}")
    if not hit or not mechs.get(theta):
        return None
    return {"displacement": mechs[theta], "source": f"the sweep's direction {hit[2]:g} deg"}


def _at(data: dict, theta: float, start: dict | None = None, changes: dict | None = None) -> dict:
    """The analysis in one direction (step 2 where it applies, also from ``start``, a collapse
    state found in the sweep) with the code check there, with the settings ``changes``."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.scene import load_scene

    r = analyse(load_scene(_turn(data, theta, verdict=True)), method="auto", options=Options(settings=changes or {}),
                nlp_options=None if start is None else {"dem_state": start}).data
    return {"lp": r.get("lp"), "nlp": r.get("nlp"), "verdict": r.get("verdict")}
