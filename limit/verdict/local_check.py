"""The code check of a local mechanism from an analysis result: its mechanism's linear
kinematic quantities (:mod:`limit.verdict.kinematic_check`), its capacity curve
(:mod:`limit.verdict.capacity_curve` for rocking mechanisms, :mod:`limit.incremental_curve`
where a joint slides, passed in by the top-level callers; 2D and 3D)
and the verdict against a demand (:mod:`limit.model.seismic_demand`)."""
from __future__ import annotations

from limit.verdict.kinematic_check import FC_DEFAULT
from limit.model.seismic_demand import G, Demand, as_dict, check
from limit.solve.status import CheckStatus, Status


def step_mechanism(res: dict) -> tuple[str, float, dict] | None:
    """(step, alpha, mechanism) of a result file's content: the frictional step 2 where it gave
    one, else the LP's; None without either."""
    for step in ("nlp", "lp"):
        part = res.get(step) or {}
        if part.get("status") == Status.OPTIMAL and part.get("mechanism") and part.get("alpha") is not None:
            return step, float(part["alpha"]), part["mechanism"]
    return None


def verdict(scene, res: dict, demand: Demand | None = None, fc: float | None = None, sliding=None) -> dict:
    """The code check of the mechanism of an analysis result ``res`` (:func:`limit.analyse`'s,
    public or not): {"step" ("nlp" or "lp": whose mechanism), "alpha0", "linear" (M*, e*, a0*,
    ...), "curve" (alpha(d), spectral quantities; None with "curve_reason" when the mechanism
    cannot be followed), "check" (None without a demand), "demand"}. ``demand`` and ``fc``
    default to the scene's (its "demand" key; FC 1.35); ``sliding``: as :func:`capacity_curve`.
    Raises ValueError when the result has no mechanism (infeasible, unbounded or failed), naming
    its status."""
    from limit.verdict.kinematic_check import linear

    demand = scene.demand if demand is None else demand
    fc = (scene.fc or FC_DEFAULT) if fc is None else fc
    m = step_mechanism(res)
    if m is None:
        lp = res.get("lp") or {}
        raise ValueError(f"no mechanism to check: the LP is {lp.get('status')}"
                         + (f" ({lp.get('reason')})" if lp.get("reason") else ""))
    step, alpha0, mech = m
    lin = linear(scene, mech, alpha0, fc)
    curve, why = capacity_curve(scene, mech, alpha0, fc, sliding)
    sp = (curve or {}).get("spectral") or {}
    c = check(demand, lin["a0_star"], sp.get("du_star"), sp.get("Ts"), sp.get("au_star")) if demand is not None else None
    return {"scene": scene.name, "step": step, "alpha0": alpha0, "linear": lin, "curve": curve,
            "curve_reason": why, "check": c, "demand": None if demand is None else as_dict(demand)}


def capacity_curve(scene, mech: dict, alpha0: float, fc: float = FC_DEFAULT, sliding=None) -> tuple[dict | None, str]:
    """(curve, "") of a mechanism, or (None, why not): the kinematic-chain follower
    (:func:`limit.verdict.capacity_curve.follow`) for a rocking mechanism; where a joint slides,
    ``sliding(scene, alpha0, mechanism=, fc=)``, the incremental limit analysis that the top-level
    callers pass (:func:`limit.incremental_curve.follow_frictional`: it solves step 2, a layer above
    this one), or no curve without it."""
    from limit.verdict.capacity_curve import SlidingJoint, follow

    try:
        return follow(scene, mech, alpha0, fc=fc), ""
    except SlidingJoint as exc:
        if sliding is None:
            return None, str(exc)
    except ValueError as exc:
        return None, str(exc)
    try:
        return sliding(scene, alpha0, mechanism=mech, fc=fc), ""
    except ValueError as exc:
        return None, str(exc)


def scene_verdict(scene, res: dict, sliding=None) -> dict:
    """The result file's "verdict" of a scene with a demand: :func:`verdict`, or {"status":
    "failed", "reason"} when the analysis gave no mechanism to check."""
    try:
        return {"status": CheckStatus.DONE, **verdict(scene, res, sliding=sliding)}
    except ValueError as exc:
        return {"status": CheckStatus.FAILED, "reason": str(exc)}


def verdict_lines(a: dict) -> list[str]:
    """Sentences of :func:`verdict`'s result (lengths in mm, accelerations in m/s^2): the
    linear quantities, the capacity curve (or why none), the checks (or why not made). One
    wording for ``limit check`` and the report."""
    q = a["linear"]
    out = [f"Mechanism of the {a['step'].upper()}, alpha0 = {a['alpha0']:.6g}: M* = {q['M_star']:.6g} kg"
           + (f" of {q['sum_P'] / G:.4g} kg moving" if "sum_P" in q else "")
           + f", e* = {q['e_star']:.4f}, a0* = {q['a0_star']:.4f} m/s^2 = {q['a0_star_g']:.4f} g (FC = {q['fc']:g})."]
    curve = a.get("curve") or {}
    sp = curve.get("spectral") or {}
    how = (f" (incremental limit analysis, {curve.get('steps')} steps: a joint slides)"
           if curve.get("method") == "incremental" else "")
    if sp.get("du_star") is not None:
        out.append(f"Capacity curve{how}: d0* = {sp['d0_star'] * 1e3:.1f} mm, du* = {sp['du_star'] * 1e3:.1f} mm, "
                   f"ds* = {sp['ds_star'] * 1e3:.1f} mm, as* = {sp['as_star']:.3f} m/s^2, Ts = {sp['Ts']:.3f} s"
                   + (f", a*(du*) = {sp['au_star']:.3f} m/s^2." if sp.get("au_star") is not None else "."))
    elif a.get("curve_reason"):
        out.append(f"No capacity curve: {a['curve_reason']}.")
    elif curve:
        out.append(f"Capacity curve{how}: alpha does not reach 0 ({curve.get('stop')}): no du*.")
    return out + check_lines(a.get("check"))


def check_lines(c: dict | None) -> list[str]:
    """Sentences of a code check (:func:`limit.model.seismic_demand.check`'s result; none without one)."""
    if not c:
        return []
    li = c["linear"]
    out = [f"Linear check: a0* = {li['capacity']:.4f} against {li['demand']:.4f} m/s^2, ratio "
           f"{li['ratio']:.3f}: " + ("PASS" if li["pass"] else "FAIL") + "."]
    nl = c.get("nonlinear")
    if nl:
        rule = nl.get("rule", "SDe(Ts)")
        where = (f" (the floor spectrum at Z, T_SLV = {nl['period']:.3f} s)" if rule == "SDeZ(T_SLV)" else "")
        out.append(f"Nonlinear check: du* = {nl['capacity'] * 1e3:.1f} mm against {rule}{where} = "
                   f"{nl['demand'] * 1e3:.1f} mm, ratio {nl['ratio']:.3f}: " + ("PASS" if nl["pass"] else "FAIL") + ".")
    else:
        out.append(f"Nonlinear check: not made ({c.get('nonlinear_reason') or 'no capacity curve'}).")
    dm = c.get("damage")
    if dm:
        out.append(f"Damage check (SLD, linear): a0* = {dm['capacity']:.4f} against {dm['demand']:.4f} m/s^2, "
                   f"ratio {dm['ratio']:.3f}: " + ("PASS" if dm["pass"] else "FAIL") + ".")
    return out


def format_assessment(a: dict) -> str:
    """Human lines of :func:`verdict`'s result."""
    return "\n".join([f"{a['scene']}:"] + [f"  {s}" for s in verdict_lines(a)])
