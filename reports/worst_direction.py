"""The report's worst-load-direction section: for each 3D scene that asked for the sweep
(``meta.sweep``, the ``sweep`` stage of :mod:`reports.stages`), alpha(theta) as a polar plot,
its minimum and the mechanism there (LP and, where step 2 ran, frictional)."""
from __future__ import annotations

from pathlib import Path


def section(results: dict, by_name: dict, figs: Path) -> list[str]:
    """Markdown lines (headings, items, images ``![alt](figures/...)``); the figures are written
    to ``figs``. Empty when no scene has a sweep."""
    from limit.direction_sweep import format_direction
    from limit.model.scene import load_scene

    from . import plots

    out = []
    for name, path in by_name.items():
        res = results.get((name, "sweep")) or {}
        if res.get("status") == "failed":
            out += [f"- **{name}**: the sweep failed ({res.get('reason')}).", ""]
        if res.get("status") != "done":
            continue
        polar = figs / f"{name}-sweep.png"
        plots.direction_polar(res, polar, name)
        at = res.get("min_nlp") or {}
        lp, nlp = at.get("lp") or {}, at.get("nlp") or {}
        fric = (f"frictional step 2 there {nlp['alpha']:.4g}" if nlp.get("status") == "optimal" and
                nlp.get("alpha") is not None else f"step 2 there: {nlp.get('status', 'not run')}"
                + (f" ({nlp['reason']})" if nlp.get("reason") else ""))
        along = res["alpha"][0]
        v = at.get("verdict") or {}
        li = ((v.get("check") or {}).get("linear")) if v.get("status") == "done" else None
        if li:
            fric += (f"; the code check there: a0* = {li['capacity']:.3f} against {li['demand']:.3f} m/s^2, ratio "
                     f"{li['ratio']:.2f} ({'passes' if li['pass'] else 'fails'})")
        if res.get("min_theta_frictional") is not None:
            at_f = ((res.get("min_frictional") or {}).get("nlp") or {})
            moved = (res.get("neighbour_passes") or {}).get("improved") or {}
            fric += (f"; step 2 in every direction: frictional minimum {res['min_alpha_frictional']:.4g} at "
                     f"{res['min_theta_frictional']:g} deg"
                     + (" (not the LP's worst direction)" if res['min_theta_frictional'] != res['min_theta'] else "")
                     + f", along the scene's own direction {res['alpha_frictional'][0]:.4g}"
                     + (f"; {len(moved)} direction(s) went lower from a neighbouring direction's collapse state"
                        if moved else "")
                     + (f" (there: {at_f.get('route')})" if at_f.get("route") == "dem-start" else ""))
        out += [f"- **{name}**: {len(res['theta'])} directions every {360 / len(res['theta']):g} degrees "
                f"({res.get('solved', len(res['theta']))} solved" + (", the rest mirrored: declared symmetric)"
                                                                       if res.get("mirror") else ")")
                + f"; along the scene's own direction (0 deg) LP alpha {along:.4g}; minimum LP alpha "
                f"{res['min_alpha']:.4g} at {res['min_theta']:g} deg (counter-clockwise seen from above"
                + ("" if res.get("min_direction") is None else
                   f", live direction {format_direction(res['min_direction'])}")
                + f"), {fric}; "
                f"{res['time_s']:.1f} s.", "", f"![worst load direction of {name}](figures/{polar.name})"]
        mech = figs / f"{name}-sweep-mechanism.png"
        if lp.get("mechanism") and plots.mechanism_figure(load_scene(path), at, None, mech):
            out.append(f"![mechanism of {name} at {res['min_theta']:g} deg](figures/{mech.name})")
        out.append("")
    if not out:
        return []
    return ["## Worst load direction (3D)", "",
            "The live body force turned about the vertical in steps; the associative LP per direction, "
            "step 2 at the minimum, and in every direction where the scene asks (meta.sweep.frictional) "
            "(limit/direction_sweep.py).", ""] + out
