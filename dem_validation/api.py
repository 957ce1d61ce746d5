"""``run_scene``: the DEM pushover of one scene, as the ``dem`` part of a result
file (docs/formats.md, 'Result file').

The ``dem`` dict:

* ``status``: ``collapsed`` | ``stable`` (no collapse up to ``alpha_max``, or
  nothing can move) | ``failed`` (with ``reason``: YADE missing, crashed,
  timed out, NaN, inconsistent runs).
* ``alpha``: the load factor extrapolated to rigid contacts (null unless
  collapsed); ``alpha_uncertainty``: worst-case effect of the bisection
  brackets on it.
* ``runs``: per contact stiffness (softest first) ``eps``, ``kn`` (N/m^3),
  ``status``, raw ``alpha`` (bracket midpoint), ``alpha_lo``, ``alpha_hi``,
  ``steps``, ``dt`` (s); ``extrapolation``: the Richardson fit
  (:mod:`dem_validation.extrapolate`).
* ``displacement``: per free block id, its motion over the collapse at the
  stiffest contacts (from the last equilibrium to where the collapse was
  detected), laid out like the LP mechanism: ``[ux, uy, rz]`` in 2D,
  ``[ux, uy, uz, rx, ry, rz]`` in 3D (m, rad; global axes, rotations
  counter-clockwise / right-handed positive).
* ``history``: every load step (``eps``, ``phase``, ``alpha``, ``outcome``,
  ``why``, ``steps``, ``residual``, ``motion`` m, ``control`` m: the live-load
  work-conjugate displacement from the settled state) - the load-displacement
  history.
* ``time_s`` (wall clock, s), ``steps``, ``params`` (every knob used).
"""
from __future__ import annotations

import time

import numpy as np

from . import params as P
from .extrapolate import richardson
from .job import build_job, unmodelled
from .runner import failed, run_job


def run_scene(scene_or_path, *, timeout_s: float | None = 1800.0, progress=None, yade: str | None = None,
              keep_dir: bool = False, contact: str = "vertex", engine: str = "yade",
              cpu_limit_s: float | None = None, **knobs) -> dict:
    """DEM pushover of a scene (a :class:`limit.model.scene.Scene`, a scene dict or a path).

    ``engine``: ``yade`` (compliant contacts, extrapolated to rigid ones; the default)
    or ``lmgc90`` (rigid contacts, non-smooth contact dynamics: :mod:`dem_validation.lmgc`,
    whose knobs are :data:`dem_validation.lmgc_main.KNOBS`; ``contact`` and ``yade``
    do not apply).

    ``knobs``: see :data:`dem_validation.params.KNOBS` (ValueError for an unknown or
    bad one). ``timeout_s``: wall-clock limit of the YADE run (None: none); ``cpu_limit_s``: limit
    of the engine's CPU seconds (None: none), which a busy machine does not use up.
    ``progress(dict)``: called with progress records (eps, alpha, step, residual).
    ``yade``: the YADE executable (default $DEM_YADE or ``yade`` on PATH).
    ``contact``: the block model, ``vertex`` (vertex spheres against faces, the
    default) or ``polyhedra`` (YADE's Polyhedra, 10-25x slower).
    Raises :class:`limit.errors.SceneError` for a rejected scene; every DEM fault
    is returned as ``{"status": "failed", "reason": ...}``.
    """
    from limit.model.scene import Scene, load_scene

    if engine not in ("yade", "lmgc90"):
        raise ValueError(f"engine: expected yade or lmgc90, got {engine!r}")
    if engine == "lmgc90":
        from .lmgc import run_loaded_lmgc90
        from .lmgc_main import knobs as lmgc_knobs

        lmgc_knobs(knobs)  # bad knobs before the scene
        scene = scene_or_path if isinstance(scene_or_path, Scene) else load_scene(scene_or_path)
        return run_loaded_lmgc90(scene, knobs, timeout_s=timeout_s, progress=progress, keep_dir=keep_dir,
                                 cpu_limit_s=cpu_limit_s)
    p = P.check(knobs, contact)
    scene = scene_or_path if isinstance(scene_or_path, Scene) else load_scene(scene_or_path)
    return run_loaded(scene, p, timeout_s=timeout_s, progress=progress, yade=yade, keep_dir=keep_dir,
                      contact=contact, cpu_limit_s=cpu_limit_s)


def run_loaded(scene, p: dict, *, timeout_s=None, progress=None, yade=None, keep_dir=False, interfaces=None,
               contact="vertex", cpu_limit_s=None) -> dict:
    """run_scene for a loaded scene and checked knobs ``p``."""
    from limit.geom.interfaces import find_interfaces
    from limit.model.loads import dead_and_live

    t0 = time.monotonic()
    used = {k: (list(v) if isinstance(v, (list, tuple)) else v) for k, v in p.items()}
    if not len(scene.free):
        return {"status": "stable", "alpha": None, "note": "no free block: nothing can move",
                "time_s": 0.0, "params": used}
    compound = [b.id for b in scene.blocks if b.parts]
    if compound and contact == "polyhedra":
        return failed(f"contact polyhedra: one convex body per block, and block '{compound[0]}' is compound "
                      "(the vertex model, the default, clumps its parts)", time_s=0.0, params=used)
    I = find_interfaces(scene) if interfaces is None else interfaces
    why = unmodelled(I, scene, ties=contact == "vertex", bonds=contact == "vertex")
    if why:
        return {"status": "skipped", "alpha": None, "reason": why, "time_s": 0.0, "params": used}
    f0, fL = dead_and_live(scene)
    try:
        job = build_job(scene, I, f0, fL, p, contact=contact)
    except ValueError as exc:  # e.g. vertex spheres that do not fit a block at these knobs
        return failed(f"cannot build the DEM model: {exc}", time_s=time.monotonic() - t0, params=used)
    raw = run_job(job, yade=yade, timeout_s=timeout_s, progress=progress, keep_dir=keep_dir, cpu_limit_s=cpu_limit_s)
    out = assemble(raw, p)
    out["time_s"] = time.monotonic() - t0
    out["params"] = used
    out["contact"] = contact
    return out


def assemble(raw: dict, p: dict) -> dict:
    """The ``dem`` dict from the YADE side's result (``{"status": "done"|"failed", "runs"}``)."""
    if raw.get("status") != "done":
        return failed(raw.get("reason", "DEM run failed"), **_keep(raw, "steps_total", "cpu_s", "progress"))
    runs = raw.get("runs") or []
    history = [dict(h, eps=r["eps"]) for r in runs for h in r.get("history", [])]
    summary = [{k: r.get(k) for k in ("eps", "kn", "status", "alpha", "alpha_lo", "alpha_hi", "steps", "dt",
                                      "sphere_radius", "mass_factor", "dead_load_collapse") if k in r} for r in runs]
    base = {"runs": summary, "history": history, "steps": sum(r.get("steps", 0) for r in runs),
            **_keep(raw, "cpu_s", "fixed_addresses")}
    if not runs:
        return failed("the YADE side returned no run", **base)
    pens = [h["penetration_ratio"] for h in history if h.get("outcome") == "stable" and "penetration_ratio" in h]
    if pens:
        base["penetration_ratio"] = max(pens)
        if max(pens) > p["pen_limit"]:
            return failed(f"contact penetration {max(pens):.2g} x r at an equilibrium, above pen_limit = "
                          f"{p['pen_limit']:g}: the vertex spheres are too small for these contact forces "
                          "(raise vertex_r or the stiffness)", **base)
    # with more than two runs only the two stiffest decide: the softer ones may lie outside the range
    # where alpha approaches the rigid value (a soft arch sags under its own weight), and the vertex
    # model adds stiffer runs until the two stiffest agree
    all_runs, runs = runs, sorted(runs, key=lambda r: -r["eps"])[-2:]
    base["runs_used"] = [r["eps"] for r in runs]
    kinds = ["collapsed under the dead load" if r.get("dead_load_collapse") else r["status"] for r in runs]
    if len(set(kinds)) > 1:
        return failed("the contact stiffnesses disagree: " + ", ".join(
            f"eps={r['eps']:g} {k}" for r, k in zip(runs, kinds)), **base)
    if runs[0].get("dead_load_collapse"):
        return {"status": "collapsed", "alpha": None, "dead_load_collapse": True,
                "note": "collapses under the dead load alone (alpha <= 0)",
                "displacement": all_runs[-1].get("displacement"), **base}
    if kinds[0] == "stable":
        return {"status": "stable", "alpha": None,
                "note": f"no collapse up to alpha_max = {p['alpha_max']:g}", **base}
    if kinds[0] != "collapsed":
        return failed(f"unexpected run status {kinds[0]!r}", **base)
    eps = [r["eps"] for r in runs]
    alpha = [r["alpha"] for r in runs]
    half = [0.5 * (r["alpha_hi"] - r["alpha_lo"]) for r in runs]
    bad = _not_asymptotic(eps, alpha, half, NO_TREND_RTOL)
    if bad:
        return failed(bad, **base)
    extra = {}
    if _not_asymptotic(eps, alpha, half, MONOTONE_RTOL):
        # a stiffer run a little below a softer one: no trend to extrapolate (friction makes the
        # loading path matter), so the stiffest run's alpha, with the spread as its uncertainty
        spread = abs(alpha[0] - alpha[1]) + half[1]
        fit = {"alpha_rigid": alpha[1], "uncertainty": spread, "correction": 0.0,
               "method": "stiffest run (no trend with the stiffness)"}
        extra["note"] = (f"not extrapolated: the stiffer run collapsed {100 * (alpha[0] - alpha[1]) / alpha[0]:.1f} %"
                         f" earlier than the softer one (within {100 * NO_TREND_RTOL:g} %, no trend with the "
                         "stiffness); alpha is the stiffest run's, its uncertainty the spread")
    else:
        fit = dict(richardson(eps, alpha, half, p["extrapolation_exponent"]), method="richardson")
    if not np.isfinite(fit["alpha_rigid"]):
        return failed("non-finite extrapolated alpha", **base)
    return {"status": "collapsed", "alpha": fit["alpha_rigid"], "alpha_uncertainty": fit["uncertainty"],
            "extrapolation": fit, "displacement": runs[-1].get("displacement"), **extra, **base}


#: a stiffer run may fall below a softer one by this much (relative) beyond their brackets
#: and still be extrapolated
MONOTONE_RTOL = 0.02
#: up to this much below, the runs show no trend: the stiffest run's alpha is the result (seen on
#: the frictional Fig. 5 trilithon: 0.0862 at eps 2.5e-6, 0.0835 at 6.25e-7, the LA 0.0833)
NO_TREND_RTOL = 0.05


def _not_asymptotic(eps, alpha, half, rtol=MONOTONE_RTOL) -> str:
    """Why the runs cannot be extrapolated, or "".

    Stiffer contacts carry at least as much as softer ones (rocking: the toe moves out
    to the edge; sliding: no change). A stiffer run that collapses clearly earlier
    (by more than ``rtol`` beyond the two brackets) means the softer contacts
    were out of the asymptotic range (seen on arches at eps = 3e-4: the soft arch
    sagged into another mechanism), and extrapolating would give a wrong number."""
    order = sorted(range(len(eps)), key=lambda k: -eps[k])
    for soft, stiff in zip(order, order[1:]):
        slack = half[soft] + half[stiff] + rtol * abs(alpha[soft])
        if alpha[stiff] < alpha[soft] - slack:
            return (f"stiffer contacts collapsed earlier (alpha {alpha[stiff]:.4g} at eps {eps[stiff]:g} < "
                    f"{alpha[soft]:.4g} at eps {eps[soft]:g}): the runs are not in the range where alpha "
                    f"approaches the rigid value as eps^p; rerun with stiffer contacts (smaller eps)")
    return ""


def _keep(d, *keys):
    return {k: d[k] for k in keys if k in d}
