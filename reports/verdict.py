"""The report's engineering verdict: the code check of the local mechanism of every catalog
scene that states a seismic demand (its "demand" key; the check itself is the LA result's
"verdict", limit.verdict.local_check), with the formulas and their sources."""
from __future__ import annotations

from limit.verdict.local_check import check_lines, step_mechanism, verdict_lines

#: (step, alpha, mechanism) of an LA result: one home, in the library
la_mechanism = step_mechanism

FORMULAS = ("Formulas: participating mass M* = (sum P_i dx_i)^2 / (g sum P_i dx_i^2), mass fraction "
            "e* = g M* / sum P_i, spectral activation acceleration a0* = alpha0 g / (e* FC) (Circolare 617/2009 "
            "eqs. C8A.4.3-4, kept by the 2019 Circolare C8.7.1); linear check a0* >= ag S / q (C8A.4.9; above "
            "ground also Se(T1) psi(Z) gamma / q); capacity curve alpha(d) by following the mechanism at finite "
            "displacement to alpha = 0 at d0 (rocking mechanisms by their joint equations, sliding and mixed ones by "
            "incremental limit analysis: step 2 re-solved on the displaced geometry), "
            "d* = d sum P_i dx_i^2 / (dx_k sum P_i dx_i), du* = 0.4 d0*, Ts = 2 pi sqrt(ds*/as*) at ds* = 0.4 du* "
            "(C8A.4.2, C8A.4.5-7); nonlinear check du* >= SDe(Ts) = Se(Ts) (Ts / 2 pi)^2 (C8A.4.10, at ground "
            "level) with the elastic spectrum of NTC 2018 3.2.3.2.1; above ground du* >= SDeZ(T_SLV), the floor "
            "displacement spectrum of the 2019 Circolare (C7.2.3 [C7.2.5]-[C7.2.10], first mode; [C8.7.1.12]) at "
            "T_SLV = 1.68 pi sqrt(du* / a*(du*)) ([C8.7.1.10]), with the building's damping xi1 as a fraction in "
            "1.1 xi1^-0.5 (limit/model/seismic_demand.py says why). P_i: the blocks' weights; dx_i: their "
            "centroids' horizontal virtual displacements in the mechanism of the limit analysis (frictional where "
            "it ran).")


def kinematic_curve(scene, la: dict) -> dict | None:
    """The LA mechanism followed at finite displacement
    (:func:`limit.verdict.local_check.capacity_curve`: rocking, sliding and mixed mechanisms), or
    None: the verdict's curve when the scene states a demand, else followed here."""
    from limit.incremental_curve import follow_frictional
    from limit.verdict.local_check import capacity_curve

    v = (la or {}).get("verdict") or {}
    if v.get("curve"):
        return v["curve"]
    m = la_mechanism(la or {})
    if m is None:
        return None
    return capacity_curve(scene, m[2], m[1], sliding=follow_frictional)[0]


def _demand_line(d: dict, fc: float) -> str:
    where = "at ground level" if not d.get("Z") else (f"base at Z = {d['Z']:g} m of a {d['H']:g} m, {d['N']}-storey "
                                                        f"building with T1 = {d['T1']:g} s")
    return (f"demand ag = {d['ag_g']:g} g, S = {d['S']:g}, F0 = {d['F0']:g}, TB = {d['TB']:g} s, TC = {d['TC']:g} s, "
            f"TD = {d['TD']:g} s, q = {d['q']:g}, {where}; confidence factor FC = {fc:g}")


def scene_lines(name: str, dim: int, v: dict) -> list[str]:
    """Markdown lines of one scene's verdict (the LA result's "verdict")."""
    if v.get("status") != "done":
        return [f"**{name}**: no check ({v.get('reason')})."]
    return [f"**{name}** ({dim}D; {_demand_line(v['demand'], v['linear']['fc'])})."] + verdict_lines(v)


#: the worked example's illustration of a mechanism above ground: the first 3D scene's demand with
#: the mechanism's base at Z of a building (H m, N storeys, first period T1 s, damping xi1)
ABOVE_GROUND = {"Z": 6.0, "H": 9.0, "N": 3, "T1": 0.3, "xi1": 0.1}


def above_ground_lines(name: str, v: dict) -> list[str]:
    """Markdown lines of the checks of a verdict ``v`` redone with its demand moved above
    ground (:data:`ABOVE_GROUND`; the capacity is the same mechanism's)."""
    from limit.model.seismic_demand import Demand, check

    sp = (v.get("curve") or {}).get("spectral") or {}
    d = Demand(**{**v["demand"], **ABOVE_GROUND})
    c = check(d, v["linear"]["a0_star"], sp.get("du_star"), sp.get("Ts"), sp.get("au_star"))
    lines = check_lines(c)
    a = ABOVE_GROUND
    return [f"**{name}, above ground** (illustrative: the same demand and mechanism with its base at Z = {a['Z']:g} m "
            f"of a {a['H']:g} m, {a['N']}-storey building, T1 = {a['T1']:g} s, building damping xi1 = {a['xi1']:g}, "
            f"mechanism damping {d.xi_mech:g})."] + lines


def worked_example(results: dict, by_name: dict) -> list[str]:
    """Markdown lines of the verdicts of the scenes stating a demand (empty without any); the
    first 3D one also above ground (:func:`above_ground_lines`)."""
    out, above = [], False
    for name in by_name:
        la = results.get((name, "la")) or {}
        v = la.get("verdict")
        if v:
            out += [f"- {s}" for s in scene_lines(name, la.get("dim"), v)] + [""]
            if not above and la.get("dim") == 3 and v.get("status") == "done":
                above = True
                out += [f"- {s}" for s in above_ground_lines(name, v)] + [""]
    if not out:
        return []
    return ["## Engineering verdict: the code check of the local mechanism", "",
            "For each catalog scene that states a seismic demand (its `demand` key; the demands here are "
            "illustrative, a site with ag = 0.2 g on soil C), the result file's `verdict`:", "", FORMULAS, ""] + out
