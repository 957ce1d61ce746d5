"""The DEM pushover's knobs: defaults, units and checks.

Lengths are relative to L, the mean size (2 x largest centroid-vertex
distance) of the free blocks, or to H, the size of the free part of the
scene (bounding box diagonal of the free blocks); times to T = sqrt(H / |g|),
the time scale on which blocks fall or rock.
"""
from __future__ import annotations

import math

#: name -> (default, description). The defaults come from bench/dem_bench.py.
KNOBS = {
    "eps": (None, "settlement strains eps = rho g / kn of the contact stiffnesses, softest first "
                  "(default: 1e-5, 2.5e-6 for the vertex model; 1e-4, 1e-5 for polyhedra)"),
    "extrapolation_exponent": (None, "alpha(eps) = alpha_rigid - c eps^p: the exponent p (default: 1 for the "
                                     "vertex model, whose sphere radius and penetrations scale with eps; 1/3 "
                                     "for polyhedra)"),
    "ks_ratio": (0.5, "shear stiffness / normal stiffness of a contact (per unit area)"),
    "damping": (0.8, "Cundall local damping of the integrator (0..1)"),
    "cfl": (1.0, "time step as a fraction of the estimated critical one"),
    "step0": (0.05, "first load step (absolute alpha)"),
    "growth": (1.5, "load step growth after each equilibrium"),
    "rebracket": (1.3, "first load step at stiffer contacts: to this x the softer contacts' alpha_hi"),
    "restep": (0.1, "further load steps at stiffer contacts, as a fraction of the softer alpha"),
    "restart_frac": (0.9, "stiffer contacts restart from an equilibrium at or below this x the softer alpha"),
    "mass_quantile": (1.0, "vertex model: blocks whose contact frequency is above this quantile of all get "
                           "their mass raised to it (density scaling; the loads stay the true ones; 1: off)"),
    "jump_ramp_T": (1.0, "vertex model: a stiffer run's first load step (to restart_frac x the softer run's "
                         "alpha) is ramped over this x T"),
    "alpha_max": (10.0, "give up (status stable) when alpha reaches this without collapse"),
    "alpha_rtol": (0.005, "bisection stops when (hi - lo) <= alpha_rtol x hi"),
    "alpha_rtol_soft": (0.015, "vertex model: the same for every run but the stiffest planned one (its alpha "
                               "enters the extrapolation with 1/3 of the weight)"),
    "eq_tol": (1e-3, "equilibrium: out-of-balance force and moment / (the block's load + its contact forces)"),
    "motion_tol": (0.02, "equilibrium: block motion per check window / (eps L)"),
    "creep_disp": (0.05, "run-away needs a motion over creep_disp x eps^(1/3) x L"),
    "surge_drop": (0.3, "the first surge of motion is over when the motion per window drops below this x its peak"),
    "early_disp": (0.25, "run-away with the first surge not yet over (motion growing since the load step): "
                         "also needs a motion over this x the collapse distance (collapse_disp x eps^(1/3) x H)"),
    "rerun_frac": (0.25, "run-away: motion per window picked up again to this x the first surge's peak"),
    "collapse_disp": (0.5, "collapse when a block moved collapse_disp x eps^(1/3) x H from the last equilibrium"),
    "checks_per_T": (40, "equilibrium checks per time scale T"),
    "runaway_T": (0.3, "run-away: motion per check window not shrinking for this x T"),
    "rerun_floor": (0.5, "run-away: motion per check window above this x eps L"),
    "rerun_reach": (1.2, "run-away: blocks moved this x farther than before the motion picked up again"),
    "observe_T": (0.5, "equilibrium is not declared before this x T after a load step"),
    "vertex_r": (1e-5, "vertex model: sphere radius / Lmin (the smallest free block's largest extent)"),
    "refine_rtol": (0.05, "vertex model: when the two stiffest runs differ by more than this (relative), "
                          "one more run at a quarter of the stiffest eps"),
    "refine_max": (2, "vertex model: at most this many such extra runs"),
    "refine_cpu_s": (1500.0, "vertex model: an extra run starts only if the CPU seconds so far plus its projection "
                             "(2 x the stiffest run's) stay within this (engines/yade/refine.py)"),
    "pen_target": (0.1, "vertex model: r is at least the expected largest point penetration / pen_target"),
    "pen_limit": (0.3, "vertex model: a run fails when an equilibrium has a contact penetration above this x r"),
    "trial_T": (10.0, "step budget of one load step, in units of T"),
    "ramp_T": (0.0, "a load step is applied linearly over this x T"),
}
DEFAULTS = {k: v[0] for k, v in KNOBS.items()}
#: the defaults that depend on the block model (``contact``)
BY_CONTACT = {"vertex": {"eps": (1e-5, 2.5e-6), "extrapolation_exponent": 1.0},
              "polyhedra": {"eps": (1e-4, 1e-5), "extrapolation_exponent": 1 / 3}}

# Run-level options of run_scene (not sent to YADE).
RUN_OPTIONS = ("timeout_s", "cpu_limit_s", "progress", "yade", "keep_dir", "contact")


def check(knobs: dict, contact: str = "vertex") -> dict:
    """Defaults (those of the block model ``contact`` included) updated with ``knobs``;
    raises ValueError naming a bad knob."""
    unknown = sorted(set(knobs) - set(KNOBS))
    if unknown:
        raise ValueError(f"unknown DEM knob(s): {', '.join(unknown)} (known: {', '.join(KNOBS)})")
    if contact not in BY_CONTACT:
        raise ValueError(f"contact: expected one of {', '.join(BY_CONTACT)}, got {contact!r}")
    p = dict(DEFAULTS)
    p.update(BY_CONTACT[contact])
    p.update({k: v for k, v in knobs.items() if v is not None})
    eps = p["eps"]
    if isinstance(eps, (int, float)):
        eps = (eps,)
    try:
        eps = tuple(float(e) for e in eps)
    except (TypeError, ValueError):
        raise ValueError(f"eps: expected numbers, got {p['eps']!r}") from None
    if not eps or any(not (0 < e < 0.1) or not math.isfinite(e) for e in eps):
        raise ValueError(f"eps: each settlement strain must be in (0, 0.1), got {list(eps)}")
    if len(set(eps)) != len(eps):
        raise ValueError(f"eps: repeated values {list(eps)}")
    p["eps"] = sorted(eps, reverse=True)
    for k, v in p.items():
        if k == "eps":
            continue
        try:
            p[k] = float(v)
        except (TypeError, ValueError):
            raise ValueError(f"{k}: expected a number, got {v!r}") from None
        if not math.isfinite(p[k]):
            raise ValueError(f"{k}: must be finite, got {v!r}")
    positive = ("ks_ratio", "cfl", "early_disp", "step0", "alpha_max", "alpha_rtol", "alpha_rtol_soft", "eq_tol", "motion_tol",
                "creep_disp",
                "collapse_disp", "checks_per_T", "runaway_T", "trial_T", "extrapolation_exponent", "rebracket",
                "rerun_floor", "rerun_reach", "vertex_r", "pen_limit", "pen_target", "refine_rtol", "refine_cpu_s")
    for k in positive:
        if not p[k] > 0:
            raise ValueError(f"{k}: must be > 0, got {p[k]!r}")
    for k, lo, hi in (("damping", 0.0, 1.0), ("mass_quantile", 0.0, 1.0 + 1e-12), ("restart_frac", 0.0, 1.0),
                      ("restep", 0.0, 1.0),
                      ("surge_drop", 0.0, 1.0), ("rerun_frac", 0.0, 1.0)):
        if not lo <= p[k] < hi:
            raise ValueError(f"{k}: must be in [{lo}, {hi}), got {p[k]!r}")
    if p["growth"] < 1:
        raise ValueError(f"growth: must be >= 1, got {p['growth']!r}")
    for k in ("ramp_T", "observe_T", "refine_max", "jump_ramp_T"):
        if p[k] < 0:
            raise ValueError(f"{k}: must be >= 0, got {p[k]!r}")
    if p["rebracket"] < 1:
        raise ValueError(f"rebracket: must be >= 1, got {p['rebracket']!r}")
    return p
