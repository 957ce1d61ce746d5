"""LMGC90 entry script: ``python lmgc_main.py JOB.json`` (run by the host's runner in
its own process: LMGC90 keeps one simulation per process, and a fatal error in
its Fortran core ends the process).

Reads the job (the DEM job of :mod:`dem_validation.job` plus ``gravity`` and
the ``rigid`` knobs of :data:`KNOBS`), brackets the collapse load factor by
:func:`search` with a fresh simulation per trial (rigid contacts: no stiffness,
no extrapolation), repeats the search at halved time steps until two successive ones
agree (:func:`converge_dt`) and writes ``job["result"]``:
``{"status": "done"|"failed"|"skipped", "runs": [one run per time step, coarsest first],
"reason", "time_s"}``
("skipped": the scene needs what the wheel cannot model, e.g. per-pair friction).
Progress goes to stdout as lines ``DEMPROGRESS {json}``.
"""
import json
import math
import os
import sys
import time

#: name -> (default, meaning). Times in s, after the issue's measured recipe: gravity alone,
#: then the live load ramped in and held; collapse = a block moved collapse_rel x the scene size.
KNOBS = {
    "dt": (1e-3, "time step (s); at 1e-2 a 55-block wall at rest drifted 1.8 mm in 3 s, at 1e-3 3 um"),
    "dt_tau": (0.0, "time step rule (dimensionless): where > 0, dt becomes min(dt, dt_tau x sqrt(h / g)), h the "
                    "least bounding-box extent of the thinnest free block; 0 keeps dt. The error of alpha falls "
                    "about tenfold per halving of dt (docs/performance.md, 'The bracket on a wall outside the "
                    "catalog')"),
    "dt_halvings": (4, "the time step's convergence check: the search is repeated at dt/2, dt/4, ... (at most this "
                       "many halvings; 0: one run at dt) until two successive time steps' brackets overlap, or "
                       "until the next run would not fit in dt_cpu_s; the finest run is the result. The "
                       "27-voussoir arch collapses 8.4 % low at 1e-3 s, 2.4 % at 5e-4 s and 0.9 % at 2.5e-4 s "
                       "(docs/performance.md, 'LMGC90's time-step check')"),
    "dt_cpu_s": (600.0, "a further halving starts only if the CPU seconds spent so far plus its projection "
                        "(twice the last run's: half the time step, twice the steps) stay within this: two thirds "
                        "of the validation's least LMGC90 CPU limit (900 s), so that a projection short by half "
                        "still ends within it"),
    "t_load": (0.02, "gravity alone before the live load starts (s); rigid blocks carry their weight from the "
                     "first step, so a short settle suffices (0.1 s gave the same alphas)"),
    "t_ramp": (0.05, "the live load rises linearly to alpha x fL over this (s)"),
    "t_hold": (0.5, "then it is held this long (s), or less when the blocks come to rest; with collapse_rel "
                    "a quarter of 1e-3, an unstable trial is told at the same excess load as after 1 s (the "
                    "motion from rest grows as t^2) in 30-35 % fewer steps (same alphas on 4 scenes)"),
    "t_rest": (0.1, "after the load has been held this long (s), a trial ends as stable once no block moved "
                    "faster than v_rest over the last half of it"),
    "v_rest": (1e-5, "rest speed (m/s; rotations x the block's radius): 50x the drift of blocks at rest, "
                     "and an unstable trial 1e-4 above its collapse load outruns it within 0.1 s"),
    "collapse_rel": (2.5e-4, "collapse: a block moved this x the size of the free part of the scene (blocks "
                             "held moved 1e-6 to 1e-5 m)"),
    "step0": (0.05, "first trial alpha; the trials double until one collapses"),
    "alpha_max": (10.0, "no collapse up to this alpha: status stable"),
    "alpha_rtol": (1e-2, "bisection stops when (hi - lo) <= alpha_rtol x hi (half width 0.5 %, within the "
                         "1 % of the closed-form checks; one trial fewer than 5e-3)"),
    "hint_margin": (0.01, "with a guessed alpha (job 'hint'), the first trials are this far (relative) "
                          "below and above it"),
}


def search(trial, p: dict, emit=None, hint=None) -> dict:
    """Bracket alpha with ``trial(alpha) -> {"outcome": "stable"|"collapse", ...}``, each
    trial from rest, then bisect until hi - lo <= alpha_rtol x hi. Returns the run: status
    (collapsed|stable), alpha (bracket midpoint), alpha_lo, alpha_hi, dead_load_collapse,
    history (one record per trial), steps, displacement (the free blocks' motion in the
    last collapsing trial), held_forces (a collapsed run: ``{"alpha", "pairs"}``, the contact
    forces per block pair at the end of the stable trial at alpha_lo, where the trial gives them).

    Without a guess: alpha = 0 first (a collapse there is a dead-load collapse), then
    step0, 2 step0, ... until a collapse (or alpha_max). With a guess ``hint`` (> 0, the
    limit analysis's alpha), the trials go out from it in steps that double,
    hint x (1 +/- m (2^(k+1) - 1)) with m = hint_margin (0.99, 0.97, 0.93, ... and 1.01,
    1.03, 1.07, ...): a guess within 1 % is bracketed in two trials (and done in three), a
    guess off by 50 % in six. A stable loaded trial has carried the dead load too (its first t_load s are the
    dead load alone), so the alpha = 0 trial is run only when every trial down from the
    guess collapsed.
    A guess only saves trials: the bracket is the trials' own."""
    history, lo, hi, collapse = [], 0.0, None, None
    forces_at = {}  # alpha -> the contact forces per block pair at the end of a stable trial

    def run(a, phase):
        t = trial(a)
        if t["outcome"] == "stable" and t.get("pair_forces") is not None:
            forces_at[a] = t["pair_forces"]
        history.append({"phase": phase, "alpha": a, "outcome": t["outcome"], "steps": t["steps"],
                        "motion": t["motion"], "control": t.get("control"), "rest": bool(t.get("rest")),
                        "settled": t.get("settled"),
                        "why": f"moved {t['motion']:.3g} m in {t['time']:.3g} s" + (", at rest" if t.get("rest") else "")})
        if emit is not None:
            emit({"phase": phase, "alpha": a, "outcome": t["outcome"], "step": sum(h["steps"] for h in history)})
        return t

    def result(status, dead=False):
        alpha = 0.5 * (lo + hi) if status == "collapsed" and hi is not None and not dead else None
        out = {"eps": 0.0, "status": status, "alpha": alpha, "alpha_lo": None if dead else lo,
               "alpha_hi": hi, "dead_load_collapse": dead, "history": history,
               "steps": sum(h["steps"] for h in history), "displacement": collapse}
        if status == "collapsed" and not dead and lo in forces_at:
            out["held_forces"] = {"alpha": lo, "pairs": forces_at[lo]}
        return out

    def dead_load():
        """The alpha = 0 trial: the dead-load collapse result when it collapses, else None."""
        nonlocal hi, collapse
        t = run(0.0, "settle")
        if t["outcome"] == "stable":
            return None
        collapse, hi = t["displacement"], 0.0
        return result("collapsed", dead=True)

    m = p["hint_margin"]
    if hint:
        a = min((1.0 - m) * hint, p["alpha_max"])
        t = run(a, "load")
        if t["outcome"] == "stable":
            lo, k = a, 0
            while hi is None:  # upwards: 1 + m, 1 + 3m, 1 + 7m, ...
                if a >= p["alpha_max"]:
                    return result("stable")
                a = min(hint * (1.0 + m * (2 ** (k + 1) - 1)), p["alpha_max"])
                t = run(a, "load")
                if t["outcome"] == "stable":
                    lo, k = a, k + 1
                else:
                    hi, collapse = a, t["displacement"]
        else:
            hi, collapse, k = a, t["displacement"], 1
            while True:  # downwards: 1 - 3m, 1 - 7m, ... while above zero
                a = hint * (1.0 - m * (2 ** (k + 1) - 1))
                if a <= 0.0:
                    dead = dead_load()
                    if dead is not None:
                        return dead
                    break
                t = run(a, "load")
                if t["outcome"] == "stable":
                    lo = a
                    break
                hi, collapse, k = a, t["displacement"], k + 1
    else:
        dead = dead_load()
        if dead is not None:
            return dead
        a = p["step0"]
        while hi is None:
            t = run(a, "load")
            if t["outcome"] != "stable":
                hi, collapse = a, t["displacement"]
                break
            lo = a
            if a >= p["alpha_max"]:
                return result("stable")
            a = min(2.0 * a, p["alpha_max"])
    while hi - lo > p["alpha_rtol"] * hi:
        a = 0.5 * (lo + hi)
        t = run(a, "bisect")
        if t["outcome"] == "stable":
            lo = a
        else:
            hi, collapse = a, t["displacement"]
    return result("collapsed")


def agree(a: dict, b: dict) -> bool:
    """Two collapsed runs' brackets [alpha_lo, alpha_hi] overlap: no difference between them that
    the bisection resolves."""
    return max(a["alpha_lo"], b["alpha_lo"]) <= min(a["alpha_hi"], b["alpha_hi"])


def converge_dt(search_at, dt: float, halvings: int, hint=None, cpu_cap: float = math.inf,
                clock=time.process_time) -> tuple[list, bool | None, str]:
    """(runs, converged, why it stopped apart): ``search_at(dt, hint) -> run`` at ``dt``, then at
    dt/2, dt/4, ... (each from the previous run's alpha as its guess) until two successive runs
    :func:`agree`, ``halvings`` halvings are done, or the next run would not fit: the CPU seconds
    spent so far (``clock``) plus twice the last run's exceed ``cpu_cap``. A run that does not
    end in a collapse with a bracket (stable, or a dead-load collapse) ends the check: converged
    is None, as when ``halvings`` is 0. Each run gets its ``dt`` and ``time_s``."""
    runs = []
    t0 = clock()
    apart = lambda: False if len(runs) > 1 else None  # noqa: E731 - no check without a second run
    for k in range(int(halvings) + 1):
        t = clock()
        run = search_at(dt, hint)
        run["dt"], run["time_s"] = dt, clock() - t
        runs.append(run)
        if run["status"] != "collapsed" or run["dead_load_collapse"] or run["alpha"] is None:
            return runs, None, ""
        if k and agree(runs[-2], run):
            return runs, True, ""
        need = clock() - t0 + 2.0 * run["time_s"]
        if k < int(halvings) and need > cpu_cap:
            return runs, apart(), (
                f"a run at dt {0.5 * dt:.3g} s would bring the CPU time to about {need:.0f} s, over dt_cpu_s = "
                f"{cpu_cap:g} s")
        dt, hint = 0.5 * dt, run["alpha"]
    return runs, apart(), f"dt_halvings = {int(halvings)} halvings done" if len(runs) > 1 else ""


def knobs(given: dict) -> dict:
    """Defaults updated with ``given``; raises ValueError naming a bad knob."""
    unknown = sorted(set(given) - set(KNOBS))
    if unknown:
        raise ValueError(f"unknown LMGC90 knob(s): {', '.join(unknown)} (known: {', '.join(KNOBS)})")
    p = {k: v[0] for k, v in KNOBS.items()}
    for k, v in given.items():
        try:
            p[k] = float(v)
        except (TypeError, ValueError):
            raise ValueError(f"{k}: expected a number, got {v!r}") from None
        zero_ok = k in ("dt_tau", "dt_halvings")
        if not (math.isfinite(p[k]) and (p[k] > 0 or (zero_ok and p[k] == 0))):
            raise ValueError(f"{k}: must be a positive number{' or 0' if zero_ok else ''}, got {v!r}")
    if p["dt_halvings"] != int(p["dt_halvings"]):
        raise ValueError(f"dt_halvings: must be a whole number, got {given['dt_halvings']!r}")
    return p


def emit(info):
    print("DEMPROGRESS " + json.dumps(info), flush=True)


def main(argv) -> int:
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # lmgc_model beside this file
    job_path = argv[1] if len(argv) > 1 else ""
    try:
        with open(job_path) as fh:
            job = json.load(fh)
    except (OSError, ValueError) as exc:
        print(f"cannot read the job file {job_path!r}: {exc}", file=sys.stderr)
        return 3
    out = os.path.join(os.path.dirname(job_path), job.get("result", "result.json"))
    t0 = time.time()
    try:
        p = knobs(job.get("rigid", {}))
        from lmgc_model import RigidScene, Unsupported

        dt = p["dt"]
        if p["dt_tau"] > 0:
            dt = min(dt, p["dt_tau"] * math.sqrt(RigidScene.thinnest(job) / float(job["gravity_norm"])))
        def search_at(dt, hint):
            scene = RigidScene(job, job["gravity"], dt)
            return search(lambda a: scene.trial(a, p), p, lambda info: emit({**info, "dt": dt}), hint=hint)

        runs, converged, why = converge_dt(search_at, dt, p["dt_halvings"], hint=job.get("hint"),
                                           cpu_cap=p["dt_cpu_s"])
        res = {"status": "done", "runs": runs, "dt_converged": converged, "dt_stop": why, "params": p}
    except Unsupported as exc:
        res = {"status": "skipped", "reason": f"LMGC90 cannot model this scene: {exc}"}
    except ImportError as exc:
        res = {"status": "failed", "reason": f"LMGC90 is not installed (compas_lmgc90): {exc}"}
    except (ValueError, FloatingPointError) as exc:
        res = {"status": "failed", "reason": str(exc)}
    res["time_s"] = time.time() - t0
    with open(out + ".tmp", "w") as fh:
        json.dump(res, fh)
    os.replace(out + ".tmp", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
