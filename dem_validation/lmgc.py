"""Host side of the LMGC90 cross-check: the ``dem`` result of one scene with rigid
contacts (non-smooth contact dynamics), in the layout of :mod:`dem_validation.api`.

There is no contact stiffness, so there is one run and no extrapolation: ``alpha``
is the midpoint of the final bracket, ``alpha_uncertainty`` its half width.
``engine`` is ``"lmgc90"``; ``runs[0]`` has ``eps = 0``. The knobs are
:data:`dem_validation.lmgc_main.KNOBS`.
"""
from __future__ import annotations

import time

from .job import build_job, unmodelled
from .lmgc_main import knobs as check_knobs
from .runner import failed, run_job


def run_loaded_lmgc90(scene, knobs: dict, *, timeout_s=None, progress=None, keep_dir=False,
                      interfaces=None, hint: float | None = None, cpu_limit_s=None) -> dict:
    """LMGC90 pushover of a loaded :class:`limit.model.scene.Scene`; every fault is a failed dict.
    ``hint``: a guessed alpha (the limit analysis's) to start the bracket from; it saves
    trials, it does not enter the result."""
    from limit.geom.interfaces import find_interfaces
    from limit.model.loads import dead_and_live

    t0 = time.monotonic()
    p = check_knobs(knobs)
    base = {"engine": "lmgc90", "params": p}
    if not len(scene.free):
        return {"status": "stable", "alpha": None, "note": "no free block: nothing can move", "time_s": 0.0, **base}
    I = find_interfaces(scene) if interfaces is None else interfaces
    why = unmodelled(I, scene)
    if why:
        return {"status": "skipped", "alpha": None, "reason": why, "time_s": 0.0, **base}
    f0, fL = dead_and_live(scene)
    job = build_job(scene, I, f0, fL, {}, contact="polyhedra")
    job.update(gravity=[float(x) for x in scene.gravity], rigid=p)
    if hint is not None and hint > 0:
        job["hint"] = float(hint)
    raw = run_job(job, engine="lmgc90", timeout_s=timeout_s, progress=progress, keep_dir=keep_dir,
                  cpu_limit_s=cpu_limit_s)
    out = assemble_rigid(raw)
    out.update(time_s=time.monotonic() - t0, **base)
    return out


def assemble_rigid(raw: dict) -> dict:
    """The ``dem`` dict from the LMGC90 side's result ("skipped" with the reason when the
    scene needs what the wheel cannot model)."""
    if raw.get("status") == "skipped":
        return {"status": "skipped", "alpha": None, "reason": raw.get("reason", "")}
    if raw.get("status") != "done":
        return failed(raw.get("reason", "LMGC90 run failed"), **{k: raw[k] for k in ("cpu_s", "progress") if k in raw})
    runs = raw.get("runs") or []
    if len(runs) != 1:
        return failed(f"the LMGC90 side returned {len(runs)} runs, expected 1")
    run = runs[0]
    summary = {k: run.get(k) for k in ("eps", "status", "alpha", "alpha_lo", "alpha_hi", "steps",
                                        "dead_load_collapse")}
    base = {"runs": [summary], "history": [dict(h, eps=0.0) for h in run.get("history", [])],
            "steps": run.get("steps", 0), "displacement": run.get("displacement")}
    if run.get("dead_load_collapse"):
        return {"status": "collapsed", "alpha": None, "dead_load_collapse": True,
                "note": "collapses under the dead load alone (alpha <= 0)", **base}
    if run["status"] == "stable":
        return {"status": "stable", "alpha": None, "note": "no collapse up to alpha_max", **base}
    half = 0.5 * (run["alpha_hi"] - run["alpha_lo"])
    return {"status": "collapsed", "alpha": run["alpha"], "alpha_uncertainty": half, **base}
