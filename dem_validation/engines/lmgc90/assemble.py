"""The LMGC90 side's result as a DEM result: one run with rigid contacts, its alpha the
midpoint of the final bracket and its uncertainty the half width."""
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
    if len(runs) != 1:
        return failed(f"the LMGC90 side returned {len(runs)} runs, expected 1")
    run = runs[0]
    summary = {k: run.get(k) for k in ("eps", "status", "alpha", "alpha_lo", "alpha_hi", "steps",
                                        "dead_load_collapse", "dt") if k != "dt" or "dt" in run}
    base = {"runs": [summary], "history": [dict(h, eps=0.0) for h in run.get("history", [])],
            "steps": run.get("steps", 0), "displacement": run.get("displacement")}
    if run.get("dead_load_collapse"):
        return DemResult.of(Status.COLLAPSED, alpha=None, dead_load_collapse=True,
                            note="collapses under the dead load alone (alpha <= 0)", **base)
    if run["status"] == "stable":
        return DemResult.of(Status.STABLE, alpha=None, note="no collapse up to alpha_max", **base)
    half = 0.5 * (run["alpha_hi"] - run["alpha_lo"])
    return DemResult.of(Status.COLLAPSED, alpha=run["alpha"], alpha_uncertainty=half, **base)
