"""The limit-analysis bracket as a self-check of a dynamic result.

For rigid blocks on frictional, no-tension joints, no collapse can happen below the frictional
minimum, and the associative LP is an upper bound of every frictional collapse (Baggio &
Trovalusci, section 3; Radenkovic's theorems). Step 2's verified alpha is a frictional collapse
state, so the minimum is at or below it: a dynamic alpha below step 2's is either a lower state
that step 2 missed or something the engine adds (time step, contact compliance, inertia past a
held state, creep). The command tries the first: step 2 from the run's own state
(:func:`judge_with_start`, as ``limit solve --dem-start`` does). A dynamic alpha above the LP has no such excuse for rigid
blocks. Either is marked ``suspect``, with the reason, beyond a relative :data:`SLACK`. The
limit analysis uses the engines' friction: a near-circular cone (24 inscribed sliding faces) in
3D, the exact two faces in 2D. The inscribed polygon is up to 1 - cos(pi/24) = 0.86 % inside the
cone, so in 3D the LP's bound on the cone is the polygon's LP divided by cos(pi/24)
(:func:`cone_lp_factor`).

The paper's 3D joint takes sliding and twisting as independent (|T| <= mu N and a twisting
moment of its own), while both engines carry a joint on point contacts at its polygon's
corners, each with its own Coulomb cone, so that a joint that slides has less left to twist.
Where the two differ, the engines' joint is the weaker: a slab pushed 0.25 m off its centre
carries 0.5949 on the paper's joints and 0.5304 on point contacts (24 inscribed faces,
``tests/test_dem_bracket.py``). A 3D run still judged suspect low after the start above is
therefore judged again on point contacts (:func:`point_contact_check`: the LP and step 2 from
the run's state, ``limit solve --model vertex``).
"""
from __future__ import annotations

import math

#: relative tolerance of the bracket (the engines' own uncertainty is about 0.2-0.5 %)
SLACK = 0.01
#: sliding faces of the 3D limit analysis the engines are compared with (inscribed in the cone)
CONE_FACES = 24


def cone_lp_factor(dim: int) -> float:
    """The factor from the inscribed polygon's LP alpha to an upper bound on the circular cone's:
    scaling every sliding capacity by 1/cos(pi/n) puts the polygon around the cone, and the LP's
    alpha scales at most as much (1 in 2D, where the two faces are exact)."""
    return 1.0 / math.cos(math.pi / CONE_FACES) if dim == 3 else 1.0


def limit_analysis(scene) -> dict:
    """{"fric_alpha", "lp_alpha", "fric_status", "model"} of a scene, with the engines' friction
    (step 2 without its MILP and iterative-LP checks, and without a code check)."""
    from dataclasses import replace

    from limit.analysis import analyse
    from limit.model.assemble import Options

    model = Options(n_slide=CONE_FACES, slide_fit="inscribed") if scene.dim == 3 else Options()
    res = analyse(replace(scene, demand=None), options=model,
                  nlp_options={"global_check": False, "iterative": False, "arbitrary": False}).data
    lp, nlp = res["lp"], res.get("nlp") or {}
    fric = nlp.get("alpha") if nlp.get("status") in ("optimal", "skipped") else None
    return {"fric_alpha": fric, "lp_alpha": lp.get("alpha") if lp.get("status") == "optimal" else None,
            "fric_status": nlp.get("status"), "lp_factor": cone_lp_factor(scene.dim),
            "model": f"{CONE_FACES} inscribed sliding faces" if scene.dim == 3 else "2D, two sliding faces"}


def rising_with_dt(dem: dict) -> bool:
    """A run repeated at halved time steps (LMGC90's ``runs``, each with ``dt``) whose alpha rose at
    every halving: the finest time step still errs low, by a part of the last rise."""
    a = [r["alpha"] for r in dem.get("runs") or [] if r.get("dt") is not None and r.get("alpha") is not None]
    return len(a) >= 2 and all(y > x for x, y in zip(a, a[1:]))


def _time_step_note(dem: dict) -> str:
    if dem.get("dt_converged") is False:
        return "; this run's alpha still moved at its last halving of the time step"
    if rising_with_dt(dem):
        return "; this run's alpha rose at every halving of the time step"
    return ""


def judge(dem: dict, la: dict, slack: float = SLACK) -> dict:
    """The bracket entry of a DEM result ``dem`` against ``la`` ({"fric_alpha", "lp_alpha",
    "lp_factor" (default 1): the LP bound is lp_alpha x lp_factor}):
    {"verdict": "inside" | "suspect" | "unchecked", "side": "low" | "high" | None, "reason",
    "fric_alpha", "lp_alpha", "slack"}."""
    fric, lp = la.get("fric_alpha"), la.get("lp_alpha")
    out = {"fric_alpha": fric, "lp_alpha": lp, "slack": slack, "side": None}
    lp = None if lp is None else lp * la.get("lp_factor", 1.0)  # the bound on the engines' cone
    if la.get("model"):
        out["model"] = la["model"]
    a = dem.get("alpha")
    if dem.get("status") != "collapsed" or a is None:
        return {**out, "verdict": "unchecked", "reason": f"no collapse alpha (status {dem.get('status')})"}
    if fric is not None and a < fric * (1.0 - slack):
        return {**out, "verdict": "suspect", "side": "low",
                "reason": (f"{a:.5g} is {100 * (1 - a / fric):.1f} % below step 2's frictional collapse at {fric:.5g}: "
                           "rigid blocks cannot collapse below the frictional minimum, so either step 2 missed a "
                           "lower state (limit solve --dem-start tries this run's state) or the engine adds "
                           "something rigid blocks do not have (time step, contact compliance, inertia past a "
                           "held state, creep)"
                           + _time_step_note(dem))}
    if lp is not None and a > lp * (1.0 + slack):
        return {**out, "verdict": "suspect", "side": "high",
                "reason": (f"{a:.5g} is {100 * (a / lp - 1):.1f} % above the associative LP's upper bound {lp:.5g}: "
                           "no rigid-block collapse lies there (a locked or too stiff contact model)")}
    if fric is None:
        return {**out, "verdict": "inside" if lp is not None else "unchecked",
                "reason": ("at or below the LP's upper bound; the lower side is not checked: step 2 gave no "
                           "verified alpha") if lp is not None else "the limit analysis gave no alpha"}
    return {**out, "verdict": "inside", "reason": f"within [{fric:.5g}, {lp:.5g}] (slack {slack:.0%})"
            if lp is not None else f"at or above step 2's {fric:.5g}"}


def _assembled_lp(scene, options):
    """(P, LP solution) of ``scene`` assembled with ``options``."""
    from limit.analysis import solve_lp
    from limit.model.assemble import assemble

    P = assemble(scene, options)
    return P, solve_lp(P)[0]


def judge_with_start(scene, dem: dict, la: dict, slack: float = SLACK) -> dict:
    """:func:`judge`, and for a run judged suspect low, step 2 started from the run's own collapse
    state (:func:`limit.step2.adopt_dem_state`: the N iteration from its contact forces, then its
    motion) in the engines' friction model: the entry gets ``dem_start`` {"status", "alpha",
    "adopted"} and its outcome at the end of the reason. Where that start verifies a point lower
    than step 2's by more than the setting lower_by, step 2 had stopped above the minimum: the
    run is judged again against that point, and ``fric_alpha_step2`` keeps step 2's own. A 3D run
    still suspect low is judged on the engines' point contacts (:func:`point_contact_check`)."""
    entry = judge(dem, la, slack)
    if entry.get("verdict") != "suspect" or entry.get("side") != "low":
        return entry
    from limit.model.assemble import Options
    from limit.solve.dem_start import state_of
    from limit.step2 import adopt_dem_state

    try:
        state = state_of(dem)
    except ValueError:  # no motion recorded: nothing to start from
        return entry
    model = Options(n_slide=CONE_FACES, slide_fit="inscribed") if scene.dim == 3 else Options()
    fric = entry["fric_alpha"]
    P, sol = _assembled_lp(scene, model)
    _, ds = adopt_dem_state(P, sol, {"status": "optimal", "alpha": fric}, state)
    start = {"status": ds["status"], "alpha": ds["alpha"], "adopted": ds["adopted"]}
    if ds["adopted"]:
        again = judge(dem, {**la, "fric_alpha": ds["alpha"]}, slack)
        again = {**again, "dem_start": start, "fric_alpha_step2": fric,
                 "reason": again["reason"] + f" (step 2 from this run's state verified {ds['alpha']:.5g}, below "
                                            f"step 2's own {fric:.5g})"}
        still = again.get("verdict") == "suspect" and again.get("side") == "low" and scene.dim == 3
        return point_contact_check(scene, dem, state, again, slack) if still else again
    told = (f"verified {ds['alpha']:.5g} again: no lower rigid-block state near this run's"
            if ds["status"] == "optimal" else "verified no point")
    entry = {**entry, "dem_start": start, "reason": entry["reason"] + f"; step 2 from this run's state {told}"}
    return point_contact_check(scene, dem, state, entry, slack) if scene.dim == 3 else entry


#: the bracket's joint model on point contacts (3D): as the engines carry a joint
POINT_CONTACTS = f"point contacts at the joints' corners, {CONE_FACES} inscribed sliding faces"


def point_contact_state(scene, state: dict) -> dict:
    """The LP and step 2 from a run's state ``state`` (:func:`limit.solve.dem_start.state_of`) on
    point contacts at each contact polygon's corners (:class:`limit.model.assemble.Options` model
    "vertex", 24 inscribed sliding faces): {"status", "alpha" (None unless verified), "lp_alpha",
    "lower_by" (the scene's setting)}.
    Step 2's own search on point contacts is not run: on the cross vault it takes ten times as
    long as on the paper's joints."""
    from limit import settings
    from limit.model.assemble import Options
    from limit.solve.status import Status
    from limit.step2 import adopt_dem_state

    P, sol = _assembled_lp(scene, Options(model="vertex", n_slide=CONE_FACES, slide_fit="inscribed"))
    by = settings.of(P).lower_by
    if sol.status != Status.OPTIMAL:
        return {"status": str(sol.status), "alpha": None, "lp_alpha": None, "lower_by": by}
    _, ds = adopt_dem_state(P, sol, {"status": "failed", "alpha": None}, state)
    return {"status": str(ds["status"]), "alpha": ds["alpha"] if ds["status"] == Status.OPTIMAL else None,
            "lp_alpha": sol.alpha, "lower_by": by}


def on_point_contacts(dem: dict, entry: dict, pc: dict, slack: float = SLACK) -> dict:
    """A 3D run's bracket ``entry``, judged again on point contacts ``pc``
    (:func:`point_contact_state`). Where ``pc`` verifies a point lower than the entry's lower
    bound by more than its ``lower_by`` (the setting), the run is judged against [that point,
    that LP] (``fric_alpha_step2`` keeps step 2's own on the paper's joints); either way the entry
    gets ``point_contacts`` and the outcome at the end of its reason."""
    from limit.settings import DEFAULT
    from limit.step2 import lower

    fric, found, lp = entry["fric_alpha"], pc.get("alpha"), pc.get("lp_alpha")
    if lp is None:
        return {**entry, "point_contacts": pc,
                "reason": entry["reason"] + f"; on point contacts the LP gave no alpha ({pc.get('status')})"}
    if not lower(found, fric, pc.get("lower_by", DEFAULT.lower_by)):
        told = f"verified {found:.5g}, not lower" if found is not None else "verified no point"
        return {**entry, "point_contacts": pc,
                "reason": entry["reason"] + f"; on point contacts at the joints' corners, as the engines carry "
                                            f"them, step 2 from this run's state {told}"}
    again = judge(dem, {"fric_alpha": found, "lp_alpha": lp, "lp_factor": cone_lp_factor(3),
                        "model": POINT_CONTACTS}, slack)
    return {**again, "dem_start": entry.get("dem_start"), "point_contacts": pc,
            "fric_alpha_step2": entry.get("fric_alpha_step2", fric),
            "reason": again["reason"] + f" (on point contacts at the joints' corners, as the engines carry them: "
                                        f"step 2 from this run's state verified {found:.5g}, the LP {lp:.5g}; "
                                        f"on the paper's joints step 2 gave {fric:.5g})"}


def point_contact_check(scene, dem: dict, state: dict, entry: dict, slack: float = SLACK) -> dict:
    """A 3D run judged suspect low, judged again with the engines' joints:
    :func:`on_point_contacts` with :func:`point_contact_state` from the run's ``state``."""
    return on_point_contacts(dem, entry, point_contact_state(scene, state), slack)


def label(entry: dict | None) -> str:
    """'' for an inside or unchecked result, else 'suspect low' / 'suspect high'."""
    if not entry or entry.get("verdict") != "suspect":
        return ""
    return f"suspect {entry.get('side')}"
