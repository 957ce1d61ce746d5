"""When the vertex model runs one more, stiffer, pushover (the host's loop,
:func:`dem_validation.engines.yade.per_stiffness`). Pure Python, no YADE import.

The two stiffest runs are *apart* when they end differently (one collapsed under the dead load or
stood where the other collapsed) or collapse at alphas more than ``refine_rtol`` apart. Then one
more run at a quarter of the stiffest eps follows, at most ``refine_max`` of them, and only where
it *fits*: the CPU spent so far plus the new run's projected CPU, :data:`COST_RATIO` x the
stiffest run's, stays within ``refine_cpu_s``. A quarter of eps (4 x the stiffness) halves the
critical time step, so the same simulated time takes twice the steps (the measured ratios:
docs/performance.md, 'YADE's loading path on the 70-stone Fig. 3 wall'). The rule caps the cost
of a scene whose compliant model does not settle with the stiffness, without a knob per scene.
"""
from __future__ import annotations

#: projected CPU of a run at a quarter of eps, as a multiple of the stiffest run's so far
COST_RATIO = 2.0


def kind(run: dict) -> str:
    """How a run ended: "dead" (collapsed under the dead load), else its status."""
    return "dead" if run.get("dead_load_collapse") else run["status"]


def apart(soft: dict, stiff: dict, rtol: float) -> bool:
    """True when two runs disagree: of different kinds (:func:`kind`), or collapsed at alphas more
    than ``rtol`` apart (relative to the stiffer run's)."""
    if kind(soft) != kind(stiff):
        return True
    if kind(stiff) != "collapsed" or soft.get("alpha") is None or not stiff.get("alpha"):
        return False
    return abs(stiff["alpha"] - soft["alpha"]) > rtol * abs(stiff["alpha"])


def fits(cpu_used: float, cpu_stiffest: float, cap: float) -> bool:
    """Whether one more run fits in ``cap`` CPU seconds: ``cpu_used`` + :data:`COST_RATIO` x
    ``cpu_stiffest`` <= ``cap``."""
    return cpu_used + COST_RATIO * cpu_stiffest <= cap


def next_eps(runs: list, extra: int, cpu_used: float, p: dict) -> tuple[float | None, str]:
    """(eps of one more run or None, why not): after the planned runs, ``runs`` (each with ``eps``,
    ``status``, ``alpha``, ``cpu_s``), ``extra`` stiffer runs made so far, ``cpu_used`` CPU seconds
    spent. The reason is empty where nothing is wrong: the two stiffest agree, or there is one run."""
    if len(runs) < 2 or not apart(runs[-2], runs[-1], float(p["refine_rtol"])):
        return None, ""
    eps = runs[-1]["eps"] / 4.0
    if extra >= int(p["refine_max"]):
        return None, (f"the two stiffest runs are apart (refine_rtol {p['refine_rtol']:g}) after "
                      f"refine_max = {int(p['refine_max'])} extra run(s)")
    need = cpu_used + COST_RATIO * float(runs[-1].get("cpu_s") or 0.0)
    if not fits(cpu_used, float(runs[-1].get("cpu_s") or 0.0), float(p["refine_cpu_s"])):
        return None, (f"the two stiffest runs are apart (refine_rtol {p['refine_rtol']:g}), and a run at eps "
                      f"{eps:g} would bring the CPU to about {need:.0f} s, over refine_cpu_s = "
                      f"{float(p['refine_cpu_s']):g} s")
    return eps, ""
