"""The code check of a local mechanism from an analysis result: its mechanism's linear
kinematic quantities (:mod:`limit.kinematic_check`), the capacity curve
where the mechanism can be followed (:mod:`limit.capacity_curve`: rocking mechanisms, 2D and 3D)
and the verdict against a demand (:mod:`limit.seismic_demand`)."""
from __future__ import annotations

from .kinematic_check import FC_DEFAULT
from .seismic_demand import Demand, check


def step_mechanism(res: dict) -> tuple[str, float, dict] | None:
    """(step, alpha, mechanism) of a result file's content: the frictional step 2 where it gave
    one, else the LP's; None without either."""
    for step in ("nlp", "lp"):
        part = res.get(step) or {}
        if part.get("status") == "optimal" and part.get("mechanism") and part.get("alpha") is not None:
            return step, float(part["alpha"]), part["mechanism"]
    return None


def verdict(scene, res: dict, demand: Demand | None = None, fc: float | None = None) -> dict:
    """The code check of the mechanism of an analysis result ``res`` (:func:`limit.analyse`'s,
    public or not): {"step" ("nlp" or "lp": whose mechanism), "alpha0", "linear" (M*, e*, a0*,
    ...), "curve" (alpha(d), spectral quantities; None with "curve_reason" when the mechanism
    cannot be followed), "check" (None without a demand), "demand"}. ``demand`` and ``fc``
    default to the scene's (its "demand" key; FC 1.35). Raises ValueError when the result has
    no mechanism (infeasible, unbounded or failed), naming its status."""
    from .capacity_curve import follow
    from .kinematic_check import linear

    demand = scene.demand if demand is None else demand
    fc = (scene.fc or FC_DEFAULT) if fc is None else fc
    m = step_mechanism(res)
    if m is None:
        lp = res.get("lp") or {}
        raise ValueError(f"no mechanism to check: the LP is {lp.get('status')}"
                         + (f" ({lp.get('reason')})" if lp.get("reason") else ""))
    step, alpha0, mech = m
    lin = linear(scene, mech, alpha0, fc)
    curve, why = None, ""
    try:
        curve = follow(scene, mech, alpha0, fc=fc)
    except ValueError as exc:
        why = str(exc)
    sp = (curve or {}).get("spectral") or {}
    c = check(demand, lin["a0_star"], sp.get("du_star"), sp.get("Ts")) if demand is not None else None
    return {"scene": scene.name, "step": step, "alpha0": alpha0, "linear": lin, "curve": curve,
            "curve_reason": why, "check": c, "demand": None if demand is None else vars(demand)}


def scene_verdict(scene, res: dict) -> dict:
    """The result file's "verdict" of a scene with a demand: :func:`verdict`, or {"status":
    "failed", "reason"} when the analysis gave no mechanism to check."""
    try:
        return {"status": "done", **verdict(scene, res)}
    except ValueError as exc:
        return {"status": "failed", "reason": str(exc)}


def format_assessment(a: dict) -> str:
    """Human lines of :func:`verdict`'s result."""
    lin = a["linear"]
    out = [f"{a['scene']}: mechanism of the {a['step'].upper()}, alpha0 = {a['alpha0']:.6g}",
           f"  participating mass M* = {lin['M_star']:.6g} kg, e* = {lin['e_star']:.4f}, "
           f"a0* = {lin['a0_star']:.4f} m/s^2 = {lin['a0_star_g']:.4f} g (FC = {lin['fc']:g})"]
    sp = (a.get("curve") or {}).get("spectral") or {}
    if sp.get("du_star") is not None:
        out.append(f"  capacity curve: d0* = {sp['d0_star']:.4g} m, du* = {sp['du_star']:.4g} m, "
                   f"Ts = {sp['Ts']:.4g} s")
    elif a.get("curve_reason"):
        out.append(f"  capacity curve: none ({a['curve_reason']})")
    c = a.get("check")
    if c:
        li = c["linear"]
        out.append(f"  linear check: a0* {li['capacity']:.4f} vs {li['demand']:.4f} m/s^2, ratio {li['ratio']:.3f}: "
                   + ("PASS" if li["pass"] else "FAIL"))
        nl = c.get("nonlinear")
        if nl:
            out.append(f"  nonlinear check: du* {nl['capacity']:.4g} vs SDe(Ts) {nl['demand']:.4g} m, ratio "
                       f"{nl['ratio']:.3f}: " + ("PASS" if nl["pass"] else "FAIL"))
    return "\n".join(out)
