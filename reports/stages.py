"""The stages the validation run applies to each scene, as plain functions for the workers.

``la``: the limit analysis (LP, then the NLP where the scene needs it, with the
global MILP and the iterative LP as independent checks on small scenes);
``cone``: the same limit analysis of a 3D scene with a near-circular friction cone
(:data:`CONE_FACES` inscribed sliding faces, within 1 - cos(pi/24) = 0.86 % inside
the cone that both dynamic engines use) beside the paper's 4 circumscribed faces
(up to 41 % outside it in a diagonal direction); ``dem``: the YADE pushover;
``lmgc``: the LMGC90 pushover (rigid contacts, :mod:`dem_validation.lmgc`); ``sweep``: the
worst horizontal direction of the live load of a 3D scene that asks for it (``meta.sweep``).
A stage never raises: any fault comes back as a
result with ``status`` "failed" and its reason, so the run goes on.

A scene steers its DEM stage through ``meta.dem``: ``{"run": false, "reason":
"..."}`` opts out (the reason is shown in the report); ``{"knobs": {...},
"timeout_s": s}`` passes pushover knobs (:mod:`dem_validation.params`);
``"cpu_limit_s": s`` replaces the stage's limits (:func:`limits`);
``meta.lmgc`` does the same for the LMGC90 stage (knobs:
:data:`dem_validation.engines.lmgc90.lmgc_main.KNOBS`).
"""
from __future__ import annotations

import time
import traceback

#: CONE_FACES: sliding faces of the near-circular friction model of the ``cone`` stage
#: (inscribed), the same model as the DEM command's bracket
from dem_validation.bracket import CONE_FACES

#: limits of the independent checks in the validation run (free blocks)
GLOBAL_MAX_FREE = 12
ITERATIVE_MAX_FREE = 80
GLOBAL_TIME_LIMIT = 60.0
#: limits of one scene's stage: the engine's CPU seconds, at least these and COST_FACTOR x the
#: scene's measured cost (``meta.<stage>.cost_s``, on this project's usual 2-core machine), and
#: the wall clock, WALL_FACTOR x that, as the guard against a hung engine. The limits are in CPU
#: seconds and generous because a slower or busy machine needs several times the measured cost
#: (docs/performance.md, 'Measurements moved from code comments').
DEM_CPU_LIMIT = 1500.0
LMGC_CPU_LIMIT = 900.0
COST_FACTOR = 10.0
WALL_FACTOR = 3.0
#: LMGC90 runs in the default validation on every scene whose measured LMGC90 cost
#: (``meta.lmgc.cost_s``, CPU s on this project's 2-core machine, written by scenes/catalog.py)
#: is at most this: every catalog scene's cost is below it (the costs: docs/performance.md), and
#: the limit stays for a user's larger scenes. ``validate --lmgc-all`` (and ``make bench``) runs
#: it on every scene, and a default run shows such a cached result. How the search's cost came down: docs/performance.md, 'Catalog,
#: benchmarks and DEM stages'.
LMGC_BUDGET_S = 400.0


def la_options(scene_data: dict) -> dict:
    """The ``la`` stage's options; a scene's ``meta.la`` may raise ``global_max_free`` and
    ``global_time_limit`` (a scene whose step 2 is known to stop above a lower state gets the MILP,
    which then reports the best point and its proven lower bound: an interval)."""
    spec = (scene_data.get("meta") or {}).get("la") or {}
    return {"method": "auto", "global_max_free": int(spec.get("global_max_free", GLOBAL_MAX_FREE)),
            "iterative_max_free": ITERATIVE_MAX_FREE,
            "global_time_limit": float(spec.get("global_time_limit", GLOBAL_TIME_LIMIT))}


def limits(spec: dict, cpu_floor: float) -> dict:
    """{"cpu_limit_s", "timeout_s"} of a stage from its ``meta`` entry ``spec`` (its own limits
    when it gives them, else from its ``cost_s``; see :data:`COST_FACTOR`)."""
    cpu = spec.get("cpu_limit_s", max(cpu_floor, COST_FACTOR * float(spec.get("cost_s") or 0.0)))
    return {"cpu_limit_s": cpu, "timeout_s": spec.get("timeout_s", WALL_FACTOR * cpu)}


def dem_options(scene_data: dict) -> dict:
    spec = dict((scene_data.get("meta") or {}).get("dem") or {})
    return {"run": spec.get("run", True), "reason": spec.get("reason", ""), "knobs": spec.get("knobs", {}),
            **limits(spec, DEM_CPU_LIMIT)}


def lmgc_options(scene_data: dict, budget_s: float | None = LMGC_BUDGET_S) -> dict:
    """The LMGC90 stage's options: ``run`` False (with the reason) when the scene opts out in
    ``meta.lmgc``, or when its measured cost ``meta.lmgc.cost_s`` exceeds ``budget_s`` (None:
    no limit)."""
    spec = dict((scene_data.get("meta") or {}).get("lmgc") or {})
    run, reason = spec.get("run", True), spec.get("reason", "")
    cost = spec.get("cost_s")
    if run and budget_s is not None and cost is not None and cost > budget_s:
        run, reason = False, (f"LMGC90 costs about {cost:.0f} s here, above the default validation's "
                              f"{budget_s:.0f} s per scene (python -m reports.validate --lmgc-all, or make bench, runs it)")
    return {"run": run, "reason": reason, "knobs": spec.get("knobs", {}), **limits(spec, LMGC_CPU_LIMIT)}


def cone_options(scene_data: dict) -> dict:
    """The ``la`` stage's options with the near-circular friction model; step 2 without the
    independent MILP and iterative-LP checks (the ``la`` stage runs them; here only the
    friction model's effect on alpha is wanted)."""
    return {**la_options(scene_data), "n_slide": CONE_FACES, "slide_fit": "inscribed",
            "run": scene_data.get("dim") == 3, "global_max_free": 0, "iterative_max_free": 0}


def run_cone(path: str, options: dict) -> dict:
    """The limit analysis with the near-circular friction model (3D scenes; a 2D
    interface's two sliding faces are exact, so a 2D scene is skipped)."""
    if not options["run"]:
        return {"lp": {"status": "skipped", "alpha": None, "reason": "2D: the two sliding faces are exact"},
                "stage_time_s": 0.0}
    return run_la(path, options, curve=False)


def run_la(path: str, options: dict, curve: bool = True) -> dict:
    """Limit analysis of the scene file at ``path``: the result file's content (docs/formats.md,
    'Result file'); ``options`` may set the friction model (``n_slide``, ``slide_fit``). With
    ``curve``, also ``capacity_curve``: the mechanism followed at finite displacement
    (:func:`reports.verdict.kinematic_curve`; None where there is none), which the report draws,
    computed here in the stage's worker and cached with it rather than when the report is written."""
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.errors import SceneError
    from limit.model.scene import load_scene

    t0 = time.perf_counter()
    try:
        scene = load_scene(path)
        n_free = len(scene.free)
        nlp_opts = {"global_check": n_free <= options["global_max_free"],
                    "iterative": n_free <= options["iterative_max_free"],
                    "global_time_limit": options["global_time_limit"], "arbitrary": n_free <= options["global_max_free"]}
        model = Options(n_slide=options.get("n_slide"), slide_fit=options.get("slide_fit", "auto"))
        res = analyse(scene, method=options["method"], options=model, nlp_options=nlp_opts).data
        if curve:
            res = {**res, "capacity_curve": _curve(scene, res)}
    except SceneError as exc:
        res = {"lp": {"status": "failed", "alpha": None, "reason": f"rejected scene: {exc}"}}
    except Exception as exc:  # noqa: BLE001 - reported, never raised
        res = {"lp": {"status": "failed", "alpha": None,
                      "reason": f"{type(exc).__name__}: {exc}", "traceback": traceback.format_exc(limit=5)}}
    return {**res, "stage_time_s": time.perf_counter() - t0}


def _curve(scene, res: dict):
    """The report's capacity curve of ``res``'s mechanism, or None (also when it cannot be followed:
    the report then says there is no curve, as for a mechanism without one)."""
    from .verdict import kinematic_curve

    try:
        return kinematic_curve(scene, res)
    except Exception:  # noqa: BLE001 - a curve that cannot be followed is not a failed analysis
        return None


def run_dem(path: str, options: dict) -> dict:
    """The ``dem`` part for the scene file at ``path`` (or the opt-out record)."""
    t0 = time.perf_counter()
    if not options["run"]:
        return {"status": "skipped", "alpha": None, "reason": options["reason"] or "opted out in meta.dem",
                "time_s": 0.0}
    try:
        from dem_validation import run_scene

        res = run_scene(path, timeout_s=options["timeout_s"], cpu_limit_s=options.get("cpu_limit_s"),
                        progress=options.get("progress"), **options["knobs"])
    except Exception as exc:  # noqa: BLE001 - a fault is a result, never a crash of the run
        res = {"status": "failed", "alpha": None, "reason": f"{type(exc).__name__}: {exc}"}
    res.setdefault("time_s", time.perf_counter() - t0)
    return res


def guess_from(la: dict) -> float | None:
    """The first guess for a dynamic search from a limit-analysis result (the ``la`` stage's,
    or the ``data`` of :func:`limit.analysis.analyse`'s): step 2's (frictional) alpha where it gives one, else
    the LP's; None when neither is a positive number."""
    for part in (la.get("nlp") or {}, la.get("lp") or {}):
        if part.get("status") == "optimal" and part.get("alpha") is not None and part["alpha"] > 0:
            return float(part["alpha"])
    return None


def la_guess(scene) -> float | None:
    """:func:`guess_from` a limit analysis made here, for a run without the ``la`` stage's
    result: step 2 without its independent checks (MILP, iterative LP) and without the
    scene's code check."""
    from dataclasses import replace

    from limit.analysis import analyse

    return guess_from(analyse(replace(scene, demand=None),
                              nlp_options={"global_check": False, "iterative": False, "arbitrary": False}).data)


def run_lmgc(path: str, options: dict) -> dict:
    """The LMGC90 result for the scene file at ``path`` (or the opt-out record).

    Its search starts from a guess: ``options["hint"]`` when given (the validation run
    passes the ``la`` stage's :func:`guess_from`; None: no guess), else :func:`la_guess`.
    A guess only saves trials, the bracket is the trials' own; from the frictional alpha
    the trials start within a few per cent of the rigid-contact collapse, where the LP's
    (0.717 for the 48-block fountain, whose frictional alpha is 0.358) cost 12 trials
    instead of 8."""
    t0 = time.perf_counter()
    if not options["run"]:
        return {"status": "skipped", "alpha": None, "reason": options["reason"] or "opted out in meta.lmgc",
                "time_s": 0.0, "engine": "lmgc90"}
    try:
        from dem_validation.lmgc import run_loaded_lmgc90
        from limit.model.scene import load_scene

        scene = load_scene(path)
        if "hint" in options:
            hint = options["hint"]
        else:
            try:
                hint = la_guess(scene)
            except Exception:  # noqa: BLE001 - no guess: the search starts from step0
                hint = None
        res = run_loaded_lmgc90(scene, options["knobs"], timeout_s=options["timeout_s"], hint=hint,
                                cpu_limit_s=options.get("cpu_limit_s"), progress=options.get("progress"))
    except Exception as exc:  # noqa: BLE001 - a fault is a result, never a crash of the run
        res = {"status": "failed", "alpha": None, "reason": f"{type(exc).__name__}: {exc}", "engine": "lmgc90"}
    res.setdefault("time_s", time.perf_counter() - t0)
    return res


def sweep_options(scene_data: dict) -> dict:
    """A 3D scene asks for the worst-direction sweep with ``meta.sweep`` (``{"step": degrees,
    "frictional": bool}``, default 5 and false): most scenes do not need it, so it is opt-in; with
    ``frictional`` step 2 runs in every direction (the frictional worst direction, with the
    neighbour pass of :mod:`limit.direction_sweep`)."""
    spec = (scene_data.get("meta") or {}).get("sweep")
    return {"run": bool(spec) and scene_data.get("dim") == 3, "step": float((spec or {}).get("step", 5.0)),
            "frictional": bool((spec or {}).get("frictional", False))}


def run_sweep(path: str, options: dict) -> dict:
    """alpha over the horizontal directions of the live load (:func:`limit.direction_sweep.sweep`,
    in this worker: one process), with step 2 at the minimum (in every direction with the option
    ``frictional``); ``status`` done, skipped or failed."""
    t0 = time.perf_counter()
    if not options["run"]:
        return {"status": "skipped", "reason": "no meta.sweep (or 2D)", "time_s": 0.0}
    try:
        from limit.direction_sweep import sweep
        from limit.model.scene import load_scene

        res = sweep(load_scene(path).data, options["step"], jobs=1, every=options.get("frictional", False))
        res["status"] = "done" if res["min_theta"] is not None else "failed"
        if res["status"] == "failed":
            res["reason"] = "no direction gave an optimal LP"
    except Exception as exc:  # noqa: BLE001 - a fault is a result, never a crash of the run
        res = {"status": "failed", "reason": f"{type(exc).__name__}: {exc}"}
    res["time_s"] = time.perf_counter() - t0
    return res


STAGES = {"la": (la_options, run_la), "cone": (cone_options, run_cone), "sweep": (sweep_options, run_sweep),
          "dem": (dem_options, run_dem), "lmgc": (lmgc_options, run_lmgc)}
