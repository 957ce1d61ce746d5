"""The report's engineering verdict: a worked example of the code check of a local
mechanism (limit.kinematic_check, limit.capacity_curve, limit.seismic_demand) on catalog
scenes with a stated demand, with the formulas and their sources."""
from __future__ import annotations

from limit.local_check import step_mechanism
from limit.seismic_demand import G, Demand, check

#: the stated demand of the worked example (illustrative: a site with ag = 0.2 g on soil C)
DEMAND = Demand(ag_g=0.20, S=1.2, F0=2.5, TB=0.15, TC=0.5, TD=2.4)
#: the example scenes: a 3D wall (linear check) and a 2D rocking mechanism (linear and nonlinear)
LINEAR_SCENE = "wall-out-of-plane-3d"
NONLINEAR_SCENE = "portal-2d"
FC = 1.35


#: (step, alpha, mechanism) of an LA result: one home, in the library
la_mechanism = step_mechanism


def kinematic_curve(scene, la: dict) -> dict | None:
    """The LA mechanism followed at finite displacement (2D rocking mechanisms), or None."""
    from limit.capacity_curve import follow

    m = la_mechanism(la or {})
    if m is None or scene.dim != 2:
        return None
    try:
        return follow(scene, m[2], m[1])
    except ValueError:
        return None


def worked_example(results: dict, by_name: dict) -> list[str]:
    """Markdown lines of the worked example (empty when its scenes have no LA result)."""
    from limit.capacity_curve import follow
    from limit.kinematic_check import linear
    from limit.scene import load_scene

    d = DEMAND
    out = ["## Engineering verdict: a worked example", "",
           f"Demand (stated for the example): ag = {d.ag_g:g} g, S = {d.S:g}, F0 = {d.F0:g}, TB = {d.TB:g} s, "
           f"TC = {d.TC:g} s, TD = {d.TD:g} s, q = {d.q:g}, confidence factor FC = {FC:g} (knowledge level LC1); "
           "mechanisms at ground level.", "",
           "Formulas: participating mass M* = (sum P_i dx_i)^2 / (g sum P_i dx_i^2), mass fraction "
           "e* = g M* / sum P_i, spectral activation acceleration a0* = alpha0 g / (e* FC) (Circolare 617/2009 "
           "eqs. C8A.4.3-4, kept by the 2019 Circolare C8.7.1); linear check a0* >= ag S / q (C8A.4.9); "
           "capacity curve alpha(d) by following the mechanism at finite displacement to alpha = 0 at d0, "
           "d* = d sum P_i dx_i^2 / (dx_k sum P_i dx_i), du* = 0.4 d0*, Ts = 2 pi sqrt(ds*/as*) at ds* = 0.4 du* "
           "(C8A.4.2, C8A.4.5-7); nonlinear check du* >= SDe(Ts) = Se(Ts) (Ts / 2 pi)^2 (C8A.4.10) with the "
           "elastic spectrum of NTC 2018 3.2.3.2.1. P_i: the blocks' weights; dx_i: their centroids' "
           "horizontal virtual displacements in the mechanism of the limit analysis (frictional where it ran).", ""]
    shown = False
    for name, nonlin in ((LINEAR_SCENE, False), (NONLINEAR_SCENE, True)):
        la = (results.get((name, "la")) or {})
        m = la_mechanism(la)
        if m is None or name not in by_name:
            continue
        scene = load_scene(by_name[name])
        step, alpha0, mech = m
        q = linear(scene, mech, alpha0, FC)
        du = Ts = None
        lines = [f"**{name}** ({scene.dim}D, mechanism of the {step.upper()}, alpha0 = {alpha0:.4g}): "
                 f"M* = {q['M_star']:.4g} kg of {q['sum_P'] / G:.4g} kg moving, e* = {q['e_star']:.3f}, "
                 f"a0* = {q['a0_star']:.3f} m/s^2 = {q['a0_star_g']:.3f} g."]
        if nonlin:
            try:
                sp = follow(scene, mech, alpha0, fc=FC)["spectral"]
                du, Ts = sp.get("du_star"), sp.get("Ts")
                if du is not None:
                    lines.append(f"Capacity curve: d0* = {sp['d0_star'] * 1e3:.1f} mm, du* = {du * 1e3:.1f} mm, "
                                 f"ds* = {sp['ds_star'] * 1e3:.1f} mm, as* = {sp['as_star']:.3f} m/s^2, "
                                 f"Ts = {Ts:.3f} s.")
            except ValueError as exc:
                lines.append(f"No capacity curve: {exc}.")
        c = check(d, q["a0_star"], du, Ts)
        li = c["linear"]
        lines.append(f"Linear check: a0* = {li['capacity']:.3f} against ag S / q = {li['demand']:.3f} m/s^2, "
                     f"ratio {li['ratio']:.2f}: **{'passes' if li['pass'] else 'fails'}**.")
        nl = c["nonlinear"]
        if nl:
            lines.append(f"Nonlinear check: du* = {nl['capacity'] * 1e3:.1f} mm against SDe(Ts) = "
                         f"{nl['demand'] * 1e3:.1f} mm, ratio {nl['ratio']:.2f}: "
                         f"**{'passes' if nl['pass'] else 'fails'}**.")
        elif not nonlin:
            lines.append("Nonlinear check: not made (the finite-displacement follower handles 2D rocking "
                         "mechanisms only, so far).")
        out += [f"- {s}" for s in lines] + [""]
        shown = True
    return out if shown else []
