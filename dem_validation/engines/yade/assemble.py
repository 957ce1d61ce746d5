"""The YADE side's result as a DEM result: the two stiffest runs' alphas extrapolated to
rigid contacts (:mod:`dem_validation.extrapolate`), or why they cannot be."""
from __future__ import annotations

import numpy as np

from ...extrapolate import richardson
from ..result import DemResult, Status, failed


def assemble(raw: dict, p: dict) -> DemResult:
    """The DEM result from the YADE side's result (``{"status": "done"|"failed", "runs"}``)."""
    if raw.get("status") != "done":
        # a failed sequence keeps the runs that ended before the failure (per_stiffness)
        return failed(raw.get("reason", "DEM run failed"), **_keep(raw, "steps_total", "cpu_s", "progress", "runs"))
    runs = raw.get("runs") or []
    history = [dict(h, eps=r["eps"]) for r in runs for h in r.get("history", [])]
    summary = [{k: r.get(k) for k in ("eps", "kn", "status", "alpha", "alpha_lo", "alpha_hi", "steps", "dt",
                                      "sphere_radius", "mass_factor", "dead_load_collapse", "cpu_s", "held_forces", "held_pose") if k in r}
               for r in runs]
    base = {"runs": summary, "history": history, "steps": sum(r.get("steps", 0) for r in runs),
            **_keep(raw, "cpu_s", "fixed_addresses", "refinement")}
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
        return DemResult.of(Status.COLLAPSED, alpha=None, dead_load_collapse=True,
                            note="collapses under the dead load alone (alpha <= 0)",
                            displacement=all_runs[-1].get("displacement"), **base)
    if kinds[0] == "stable":
        return DemResult.of(Status.STABLE, alpha=None, note=f"no collapse up to alpha_max = {p['alpha_max']:g}",
                            **base)
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
    return DemResult.of(Status.COLLAPSED, alpha=fit["alpha_rigid"], alpha_uncertainty=fit["uncertainty"],
                        extrapolation=fit, displacement=runs[-1].get("displacement"), **extra, **base)


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
