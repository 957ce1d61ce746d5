"""The LMGC90 side's result as a DEM result: runs with rigid contacts at halved time steps
(coarsest first), each with its trials' history; the finest gives the alpha (the midpoint of its
final bracket, its uncertainty the half width), the top-level history and the collapse motion."""
from __future__ import annotations

from ..result import DemResult, Status, failed


def assemble_rigid(raw: dict) -> DemResult:
    """The DEM result from the LMGC90 side's result ("skipped" with the reason when the
    scene needs what the wheel cannot model)."""
    if raw.get("status") == "skipped":
        return DemResult.of(Status.SKIPPED, alpha=None, reason=raw.get("reason", ""))
    if raw.get("status") != "done":
        return failed(raw.get("reason", "LMGC90 run failed"), **{k: raw[k] for k in ("cpu_s", "progress") if k in raw})
    runs = raw.get("runs") or []
    if not runs:
        return failed("the LMGC90 side returned no run")
    run = runs[-1]
    summary = [{**{k: r.get(k) for k in ("eps", "status", "alpha", "alpha_lo", "alpha_hi", "steps",
                                         "dead_load_collapse", "dt", "time_s") if k not in ("dt", "time_s") or k in r},
                "history": [dict(h, eps=0.0) for h in r.get("history", [])]} for r in runs]
    base = {"runs": summary, "history": [dict(h, eps=0.0, **({"dt": run["dt"]} if "dt" in run else {}))
                                         for h in run.get("history", [])],
            "steps": run.get("steps", 0), "steps_total": sum(r.get("steps", 0) for r in runs),
            "displacement": run.get("displacement"), "dt_converged": raw.get("dt_converged")}
    if run.get("held_forces"):  # the finest run's: the state that --dem-start reads
        base["runs"][-1]["held_forces"] = run["held_forces"]
    if run.get("dead_load_collapse"):
        return DemResult.of(Status.COLLAPSED, alpha=None, dead_load_collapse=True,
                            note="collapses under the dead load alone (alpha <= 0)", **base)
    if run["status"] == "stable":
        return DemResult.of(Status.STABLE, alpha=None, note="no collapse up to alpha_max", **base)
    half = 0.5 * (run["alpha_hi"] - run["alpha_lo"])
    note = {}
    if raw.get("dt_converged") is False:
        a, b = runs[-2], run
        note["note"] = (f"the time step did not converge: {b['alpha']:.5g} at dt {b['dt']:.3g} s against "
                        f"{a['alpha']:.5g} at {a['dt']:.3g} s ({100 * (b['alpha'] / a['alpha'] - 1):+.1f} %, brackets "
                        f"apart; {raw.get('dt_stop') or 'no further halving'}); a smaller dt (--set dt=...), more "
                        "halvings (dt_halvings) or a larger dt_cpu_s may move it further")
    return DemResult.of(Status.COLLAPSED, alpha=run["alpha"], alpha_uncertainty=half, **note, **base)
