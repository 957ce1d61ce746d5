"""The comparison report: ``index.html`` and its Markdown twin ``index.md``.

Per scene: alpha from the LP, the NLP (and the MILP / iterative LP where run),
the DEM and the reference with its source, relative errors, run times, the
similarity of the limit-analysis mechanism and the DEM motion, a paragraph
saying where the methods agree and why they differ, and the mechanism figure.
A failed stage is shown as failed, in red, never dropped.
"""
from __future__ import annotations

import datetime as _dt
import json
import math
from pathlib import Path

import numpy as np

from . import plots, verdict, view3d, worst_direction

FAIL = {"failed"}


def _num(v, fmt=".4g"):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return format(v, fmt)


def _pct(v):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    return f"{100 * v:+.2f} %"


def explain(r) -> list[str]:
    """Sentences comparing the methods for one results row."""
    s = []
    if r.get("ref_alpha") is not None and _finite(r.get("ref_alpha")):
        s.append(f"Reference {r['ref_kind']} = {r['ref_alpha']:.6g} ({r['ref_source']}).")
    if r.get("notes"):
        s.append(str(r["notes"]))
    if r.get("pub_source"):
        if _finite(r.get("pub_alpha")):
            kind = f" ({r['pub_kind']})" if r.get("pub_kind") else ""
            s.append(f"Published: alpha = {r['pub_alpha']:.4g}{kind}, {r['pub_source']}; ours differs by "
                     f"{_pct(r.get('pub_diff'))}. {r.get('pub_note', '')}")
        else:
            s.append(f"Published ({r['pub_source']}): no number to compare. {r.get('pub_note', '')}")
    if r["lp_status"] in FAIL:
        s.append(f"The LP failed: {r['lp_reason']}")
    elif r["lp_status"] != "optimal":
        s.append(f"LP status {r['lp_status']}: {r['lp_reason']}")
    if r["nlp_status"] == "skipped":
        s.append(f"The NLP was not needed: {r['nlp_reason']}.")
    elif r["nlp_status"] == "optimal" and _finite(r["lp_alpha"]) and _finite(r["fric_alpha"]):
        gap = (r["lp_alpha"] - r["fric_alpha"]) / r["fric_alpha"]
        if gap > 1e-5:
            s.append(f"The associative LP is {100 * gap:.1f} % above the frictional value: its mechanism can "
                     "only slide with dilatancy (joints open as they slide), while the frictional mechanism "
                     "slides without opening, or opens joints that then slide at no normal force.")
        else:
            s.append("The frictional NLP ends at the LP value: friction does not lower this collapse.")
    elif r["nlp_status"] in FAIL:
        s.append(f"The NLP failed its checks: {r['nlp_reason']}")
    if r.get("global_status") == "optimal" and _finite(r.get("global_alpha")):
        at = _finite(r.get("nlp_alpha")) and abs(r["nlp_alpha"] - r["global_alpha"]) <= 1e-6 * max(1, r["global_alpha"])
        s.append(f"The mixed-integer LP proves the global frictional minimum {r['global_alpha']:.6g}; "
                 + ("the NLP reached it." if at else "the NLP stopped above it (a local solution)."))
    elif r.get("global_status") == "time_limit":
        s.append("The mixed-integer LP did not prove its optimum within its time limit"
                 + (f" (best found {r['global_alpha']:.6g})" if _finite(r.get("global_alpha")) else "")
                 + (f": the frictional minimum lies in [{r['global_lo']:.6g}, {r['global_hi']:.6g}], its proven "
                    "lower bound and step 2's checked answer." if _finite(r.get("global_lo")) else "."))
    if _finite(r.get("iter_alpha")):
        s.append(f"The iterative LP of Gilbert et al. (2006) gives {r['iter_alpha']:.6g} ({r['iter_status']}).")
    ds = r.get("dem_status")
    if ds == "collapsed" and _finite(r.get("dem_alpha")):
        d = r.get("dem_vs_la")
        txt = f"The DEM collapses at {r['dem_alpha']:.4g}"
        if _finite(r.get("dem_uncertainty")):
            txt += f" (+/- {r['dem_uncertainty']:.2g})"
        if _finite(d):
            txt += f", {100 * d:+.1f} % from the frictional limit analysis"
        s.append(txt + ".")
        if r.get("dem_model"):
            s.append(r["dem_model"])
        if _finite(d) and abs(d) > 0.02:
            s.append(dem_disagreement(r))
        if _finite(r.get("mech_similarity")):
            s.append(f"Mechanism similarity (cosine of the vertex motions, LA {r['mech_kind'].upper()} vs DEM): "
                     f"{r['mech_similarity']:.2f}.")
    elif ds == "collapsed" and r.get("dem_dead"):
        s.append("The DEM collapses under the dead load alone (no positive alpha), "
                 + ("as the limit analysis says (LP infeasible)." if r["lp_status"] == "infeasible" else
                    f"while the LP status is {r['lp_status']}."))
    elif ds == "skipped":
        s.append(f"No DEM run: {r['dem_reason']}")
    elif ds in FAIL:
        s.append(f"The DEM failed: {r['dem_reason']}")
    elif ds == "stable":
        s.append(f"The DEM did not collapse: {r['dem_reason']}")
    s += lmgc_lines(r)
    s += cone_lines(r)
    return s


def cone_lines(r) -> list[str]:
    """The friction model side by side (3D): the paper's 4 circumscribed sliding faces
    against 24 inscribed ones (within 0.86 % inside the circular cone of both dynamic
    engines), and which one the dynamic results sit closer to."""
    if not (_finite(r.get("cone_lp_alpha")) or _finite(r.get("cone_alpha"))):
        return []
    fric = f", frictional {r['cone_alpha']:.4g}" if _finite(r.get("cone_alpha")) else \
        f" (frictional step: {r.get('cone_status')})"
    txt = (f"Friction model: the numbers above use the paper's 4 sliding faces, circumscribed about the "
           f"Coulomb cone (exact along the interface axes, up to 41 % too strong diagonally); with 24 "
           f"inscribed faces (at most 0.86 % inside the cone, as in YADE and LMGC90) the LP gives "
           f"{r['cone_lp_alpha']:.4g}{fric}")
    near = [f"{n} {100 * r[k]:+.1f} %" for n, k in (("YADE", "dem_vs_cone"), ("LMGC90", "lmgc_vs_cone"))
            if _finite(r.get(k))]
    return [txt + (f"; against it: {', '.join(near)}." if near else ".")]


def lmgc_lines(r) -> list[str]:
    """What the LMGC90 run (rigid contacts) says, when it ran."""
    ls = r.get("lmgc_status")
    if not isinstance(ls, str) or not ls:  # LMGC90 did not run (None, or NaN from the table)
        return []
    if ls == "collapsed" and _finite(r.get("lmgc_alpha")):
        txt = f"LMGC90 (rigid blocks, non-smooth contact dynamics) collapses at {r['lmgc_alpha']:.4g}"
        if _finite(r.get("lmgc_uncertainty")):
            txt += f" (+/- {r['lmgc_uncertainty']:.2g})"
        if _finite(r.get("lmgc_vs_la")):
            txt += f", {100 * r['lmgc_vs_la']:+.1f} % from the frictional limit analysis"
        if _finite(r.get("dem_alpha")):
            txt += f", {100 * (r['lmgc_alpha'] / r['dem_alpha'] - 1):+.1f} % from YADE"
        out = [txt + "."]
        if isinstance(r.get("lmgc_dt"), str) and r["lmgc_dt"]:
            out.append(f"Its alpha at halved time steps: {r['lmgc_dt']}.")
        if _finite(r.get("lmgc_vs_la")) and abs(r["lmgc_vs_la"]) > 0.02:
            out.append(lmgc_disagreement(r))
        if _finite(r.get("lmgc_similarity")):
            out.append(f"Mechanism similarity, LA {r['mech_kind'].upper()} vs LMGC90: {r['lmgc_similarity']:.2f}.")
        return out
    if ls == "collapsed" and r.get("lmgc_dead"):
        return ["LMGC90 collapses under the dead load alone."]
    if ls in FAIL:
        return [f"LMGC90 failed: {r['lmgc_reason']}"]
    return [f"LMGC90: {ls}" + (f" ({r['lmgc_reason']})" if r.get("lmgc_reason") else "")]


def lmgc_disagreement(r) -> str:
    """Why LMGC90 may stand more than 2 % away from the frictional limit analysis."""
    lp, fric, lm, dem = r.get("lp_alpha"), r.get("fric_alpha"), r.get("lmgc_alpha"), r.get("dem_alpha")
    both = _finite(dem) and abs(lm / dem - 1) <= 0.03
    if _finite(lp) and _finite(fric) and lp > fric * 1.02 and fric < lm < lp * 1.01:
        txt = (f"LMGC90 lies between the frictional value and the associative LP's {lp:.4g}: with rigid blocks the "
               "contact forces are not unique, and its contact solver keeps friction engaged on joints that the "
               "frictional minimum lets open and slide, so its load sits above that minimum; the value moves with "
               "the time step and the loading rate, the mechanism is the measure here.")
    elif lm < fric and r.get("lmgc_creep"):
        txt = ("LMGC90 collapses below the limit analysis, and its trials that held never came to rest (no "
               "block below 1e-5 m/s): the blocks creep or rattle in place (a contact solver that does not converge each step on many "
               "contacts lets them sink into each other, which lowers an arch's thrust line); its value here "
               "moves with the time step "
               "(the 27-voussoir arch lost 4 % when the step went from 1e-3 to 2e-3 s, the 70-stone Fig. 3 wall "
               "23 %), so it is not a check of the limit analysis.")
    elif lm < fric:
        txt = ("LMGC90 collapses below the limit analysis: a lower bound would be violated for rigid blocks "
               "with the same interfaces, so the gap measures what the dynamic model adds (the ramp's dynamic "
               "overshoot, contacts found by the code's own detection) or a mechanism the interface model misses.")
    else:
        txt = "LMGC90 collapses above the limit analysis: its loading path selects a collapse above the minimum."
    if both:
        txt += f" YADE agrees with it ({100 * (lm / dem - 1):+.1f} %): both dynamic engines depart the same way."
    return txt


def dem_disagreement(r) -> str:
    """Why the DEM may stand away from the frictional limit analysis (a row with both)."""
    lp, fric, dem = r.get("lp_alpha"), r.get("fric_alpha"), r.get("dem_alpha")
    txt = ("The DEM follows one loading path from a settled, elastic start; the frictional limit analysis "
           "gives the lowest collapse over every stress state that friction admits. ")
    if _finite(lp) and _finite(fric) and lp > fric * 1.02 and dem > fric:
        where = "close to" if abs(dem - lp) <= 0.03 * lp else "between the frictional value and"
        txt += (f"Here the DEM lies {where} the associative LP's {lp:.4g}: joints that the frictional minimum "
                "leaves unloaded while they open and slide (a head joint acting as a hinge, a corner set "
                "against a neighbour by differential settlement) carry friction in the DEM through elastic "
                "load sharing, so the loading path selects a collapse above the minimum. This is the physics "
                "that separates step 2 from step 1, not an error of either; it is reported, not tuned.")
    elif dem < fric and _finite(r.get("iter_alpha")) and r["iter_alpha"] < 0.99 * fric:
        txt += (f"Here the DEM collapses below it, and so does the iterative LP of Gilbert et al. (2006): "
                f"{r['iter_alpha']:.4g}, a frictional collapse state {100 * (1 - r['iter_alpha'] / fric):.0f} % "
                "below the NLP's. The NLP is a local search (here it stayed at its associative start): "
                "its value is a local minimum, and the lower frictional collapse that the iterative LP "
                f"finds is the one to compare with (DEM {100 * (dem / r['iter_alpha'] - 1):+.1f} % from it).")
    elif dem < fric:
        txt += ("Here the DEM collapses below it: a lower bound would be violated for rigid blocks, so the "
                "gap measures what the DEM's contact model adds (rounded corners, elastic penetration, "
                "extrapolation to rigid contacts) or a mechanism the limit analysis's interface model misses.")
    else:
        txt += "Here the DEM collapses above it: its loading path selects a collapse above the minimum."
    return txt


def _finite(v) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v)


def _cls(status):
    return "failed" if status in FAIL else ""


def report(df, files, results: dict, out: Path, wall_time: float | None = None) -> None:
    """The catalog page: ``index.html`` (template ``catalog.html``, plotly's script shared in
    ``plotly.min.js``) and ``index.md``, with the figures under ``figures/`` and the blocks and
    motions for ParaView under ``vtk/``."""
    out = Path(out)
    figs = out / "figures"
    figs.mkdir(parents=True, exist_ok=True)
    plots.alpha_chart(df, figs / "alpha.png")
    plots.time_error(df, figs / "time_error.png")
    by_name = {json.loads(Path(p).read_text()).get("name", Path(p).stem): Path(p) for p in files}
    scenes = [_scene_figures(name, path, df, results, out) for name, path in by_name.items()]
    mech_png = {s["name"]: s["mech_png"] for s in scenes if s["mech_png"] or s["mech_failed"]}
    cap_png = {s["name"]: s["cap_png"] for s in scenes if s["cap_png"]}
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    from .table import contradictions_markdown

    bracket = ["## Dynamic results against the frictional minimum"] + contradictions_markdown(df).splitlines()
    try:
        example = bracket + verdict.worked_example(results, by_name)
    except Exception as exc:  # noqa: BLE001 - the example is noted, never fatal
        example = bracket + [f"Engineering verdict: the worked example could not be made ({type(exc).__name__}: {exc})."]
    try:
        example += worst_direction.section(results, by_name, figs)
    except Exception as exc:  # noqa: BLE001 - noted, never fatal
        example += [f"Worst load direction: the section could not be made ({type(exc).__name__}: {exc})."]
    rows = {r["name"]: r for _, r in df.iterrows()}
    for s in scenes:
        r = rows.get(s["name"])
        s.update(explain=explain(r) if r is not None else [], subtitle=_subtitle(r))
    script = view3d.script(out / "plotly.min.js") if any(s["views"] for s in scenes) else {}
    (out / "index.html").write_text(catalog_html(df, scenes, stamp, wall_time, example, script))
    (out / "index.md").write_text(_markdown(df, mech_png, stamp, wall_time, cap_png, example))


def catalog_html(df, scenes=(), stamp: str = "", wall_time: float | None = None, example=(), script=None) -> str:
    """The catalog page: the summary, the table, the overview, ``example`` (markdown lines) and
    one section per scene of ``scenes`` (:func:`_scene_figures` with ``explain`` and ``subtitle``);
    ``script``: :func:`reports.view3d.script` where the sections have interactive views."""
    return render("catalog.html", title=TITLE, stamp=stamp, wall_time=wall_time, legend=LEGEND, **(script or {}),
                  summary=summary_lines(df), head=HEAD, rows=_rows(df), blocks=md_blocks(example), scenes=list(scenes))


TITLE = "Collapse of block masonry: limit analysis against DEM"
LEGEND = ("LP: associative limit analysis (step 1); NLP: frictional, non-associative (step 2); MILP: global "
          "frictional minimum (small scenes); DEM: YADE pushover extrapolated to rigid contacts; LMGC90: rigid "
          "contacts. Errors are relative to the reference; 'DEM vs LA' relative to the frictional limit analysis. "
          "Blocks and mechanisms for ParaView: vtk/<scene>.vtk; the table: results.csv, results.parquet.")
#: the interactive view is drawn for scenes of up to this many blocks (larger ones: the static figures)
VIEW_MAX_BLOCKS = 2000


def render(template: str, **context) -> str:
    """A page from the Jinja2 templates in ``reports/templates`` (autoescaped)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(Path(__file__).resolve().parent / "templates"),
                             autoescape=jinja2.select_autoescape(["html"]), undefined=jinja2.StrictUndefined)
    return env.get_template(template).render(**context)


def md_blocks(lines) -> list[dict]:
    """Markdown lines ('## ' headings, '- ' items, '![alt](src)' images, text) as the blocks of
    the template ``blocks.html``."""
    out = []
    for line in lines:
        if line.startswith("## "):
            out.append({"kind": "h2", "text": line[3:]})
        elif line.startswith("- "):
            out.append({"kind": "item", "text": line[2:].replace("**", "")})
        elif line.startswith("![") and "](" in line and line.endswith(")"):
            alt, src = line[2:-1].split("](", 1)
            out.append({"kind": "img", "text": alt, "src": src})
        elif line:
            out.append({"kind": "p", "text": line.replace("**", "")})
    return out


def _subtitle(r) -> str:
    if r is None:
        return ""
    return f"{r['title'] or ''} {r['figure'] or ''}".strip()


def _rows(df) -> list[list[dict]]:
    """The table's cells ({"text", "cls"}) of every scene."""
    status_cols = {6: "lp_status", 7: "nlp_status", 8: "global_status", 9: "dem_status", 17: "lmgc_status"}
    return [[{"text": c, "cls": "name" if k == 0 else _cls(r.get(status_cols[k])) if k in status_cols else ""}
             for k, c in enumerate(_cells(r))] for _, r in df.iterrows()]


def _scene_figures(name: str, path: Path, df, results: dict, out: Path, views: bool = True, scene=None) -> dict:
    """One scene's figures: the VTK file, the mechanism and pushover PNGs, the interactive views
    (plotly divs, script not included); a figure that cannot be drawn is noted, never fatal.
    ``scene``: the file's loaded scene where the caller has it."""
    from limit.model.scene import load_scene

    from .vtk import joints_path, motions_of, write_joints_vtk, write_vtk

    s = {"name": name, "mech_png": None, "mech_failed": False, "cap_png": None, "views": [], "blocks": []}
    la, dem = results.get((name, "la")), results.get((name, "dem"))
    if not la:
        return s
    figs = out / "figures"
    figs.mkdir(parents=True, exist_ok=True)
    lm = results.get((name, "lmgc")) or {}
    try:
        from limit.geom.interfaces import find_interfaces

        scene = scene if scene is not None else load_scene(path)
        I = find_interfaces(scene)  # once: the joints file and the views mark the same joints
        vtk = out / "vtk" / f"{name}.vtk"
        write_vtk(scene, motions_of({**la, "dem": dem or {}, "lmgc": lm}), vtk)
        write_joints_vtk(scene, la, joints_path(vtk), interfaces=I)
        if plots.mechanism_figure(scene, la, dem, figs / f"{name}.png"):
            s["mech_png"] = f"figures/{name}.png"
        row = df[df["name"] == name]
        la_alpha = float(row["fric_alpha"].iloc[0]) if len(row) and row["fric_alpha"].iloc[0] is not None else None
        if la_alpha is None or not math.isfinite(la_alpha):
            la_alpha = float(row["lp_alpha"].iloc[0]) if len(row) and _finite(row["lp_alpha"].iloc[0]) else None
        kin = la["capacity_curve"] if "capacity_curve" in la else verdict.kinematic_curve(scene, la)
        if plots.capacity_figure(dem, la_alpha, figs / f"{name}-capacity.png", name, lmgc=lm, kinematic=kin):
            s["cap_png"] = f"figures/{name}-capacity.png"
        if views and len(scene.blocks) <= VIEW_MAX_BLOCKS:
            s["views"] = view3d.divs(scene, la, {"YADE": dem, "LMGC90": lm}, include_js=False, interfaces=I)
    except Exception as exc:  # noqa: BLE001 - a figure that cannot be drawn is noted, not fatal
        s["mech_failed"] = s["mech_png"] is None
        print(f"report: no figure for {name}: {exc}")
    return s


def scene_summary(r, la: dict | None = None) -> list[str]:
    """The opening lines of one scene's page (a results row, :func:`reports.table.row`): the
    LP, step 2 (and in 3D the same with the engines' near-circular cone), and each engine's
    alpha against the bracket [frictional alpha, LP]; with the ``la`` result, step 2's route and
    its checks too."""
    from limit.results.summary import global_interval

    def stage(alpha, status, reason, t):
        if _finite(alpha) and status in ("optimal", "skipped"):
            return f"alpha = {alpha:.6g} ({status}{'' if not _finite(t) else f', {t:.2f} s'})"
        return f"{status or 'not run'}" + (f": {reason}" if reason else "")

    out = [f"Associative LP (step 1, an upper bound): {stage(r['lp_alpha'], r['lp_status'], r['lp_reason'], r['lp_time_s'])}.",
           f"Frictional limit analysis (step 2, the answer): "
           f"{stage(r['fric_alpha'], r['nlp_status'] if r['nlp_status'] != 'failed' or _finite(r['fric_alpha']) else 'failed', r['nlp_reason'], r['nlp_time_s'])}."]
    nlp = (la or {}).get("nlp") or {}
    how = []
    if nlp.get("route"):
        how.append(f"route {nlp['route']}" + (f", start {nlp['start']}" if nlp.get("start") else ""))
    ver = nlp.get("verification") or {}
    res = [f"{k} residual {ver[k]:.1e}" for k in ("equilibrium", "yield", "complementarity")
           if isinstance(ver.get(k), (int, float))]
    if res:
        how.append("checked: " + ", ".join(res))
    g = nlp.get("global") or {}
    if g.get("status"):
        span = global_interval(nlp)
        how.append(f"global MILP {g['status']}" + (f" {g['alpha']:.6g}" if _finite(g.get("alpha")) else "")
                   + (f", the frictional minimum in [{span[0]:.6g}, {span[1]:.6g}]" if span else ""))
    if how:
        out[-1] = out[-1][:-1] + f" [{'; '.join(how)}]."
    lb = (la or {}).get("lower_bound") or {}
    if lb.get("status"):
        out.append("Lower bound with cohesion (Radenkovic: friction removed, cohesion kept): "
                   + (f"alpha = {lb['alpha']:.6g}" + (f"; the frictional minimum lies in [{lb['alpha']:.6g}, "
                                                     f"{r['fric_alpha']:.6g}]" if _finite(r['fric_alpha']) else "") + "."
                      if _finite(lb.get("alpha")) else f"{lb['status']}: {lb.get('reason', '')}."))
    if r["dim"] == 3 and _finite(r.get("cone_lp_alpha")):
        out.append(f"With the near-circular friction cone of the dynamic engines: LP {_num(r.get('cone_lp_alpha'), '.6g')}, "
                   f"step 2 {_num(r.get('cone_alpha'), '.6g')}.")
    for engine, col in (("YADE", "dem"), ("LMGC90", "lmgc")):
        st = r.get(f"{col}_status")
        if not isinstance(st, str):
            continue
        if st == "collapsed" and _finite(r.get(f"{col}_alpha")):
            u = r.get(f"{col}_uncertainty")
            br = r.get(f"{col}_bracket")
            out.append(f"{engine}: collapses at alpha = {r[f'{col}_alpha']:.4g}" + (f" +/- {u:.2g}" if _finite(u) else "")
                       + (f", {_pct(r.get(f'{col}_vs_la'))} from the frictional limit analysis" if _finite(r.get(f"{col}_vs_la")) else "")
                       + (f"; {br}: outside the bracket [frictional alpha, LP] that theory gives" if br
                          else "; inside the bracket [frictional alpha, LP]") + ".")
        else:
            out.append(f"{engine}: {st}" + (f" ({r.get(f'{col}_reason')})" if r.get(f"{col}_reason") else "") + ".")
    return out


#: a dynamic alpha within this (relative) of the frictional limit analysis agrees with it
AGREE = 0.05


def short_reason(r, col: str) -> str:
    """One line on why an engine's alpha (``col``: "dem" YADE, "lmgc" LMGC90) stands away from the
    frictional limit analysis, from the bracket theory gives (the paragraphs of :func:`explain`
    say more)."""
    a, fric, lp = r.get(f"{col}_alpha"), r.get("fric_alpha"), r.get("lp_alpha")
    br = r.get(f"{col}_bracket") or ""
    if br == "suspect high":
        return "above the LP's upper bound: suspect (the engine carries more than any rigid-block state allows)"
    if _finite(fric) and a > fric:
        near = _finite(lp) and abs(a - lp) <= 0.03 * lp
        return ("between step 2 and the LP" + (", near the LP" if near else "") + ": the loading path selects a "
                "state above the frictional minimum (joints that step 2 lets open and slide carry friction)")
    if col == "lmgc" and r.get("lmgc_creep"):
        return "below step 2, and its trials that held never came to rest: creep, a time-step artefact"
    if col == "lmgc" and str(r.get("lmgc_dt") or "").endswith("(not converged)"):
        return ("below step 2, and its alpha still moved at its last halving of the time step "
                f"({r['lmgc_dt']}): a time-step artefact")
    if col == "lmgc" and isinstance(r.get("lmgc_dt_rising"), (bool, np.bool_)) and r["lmgc_dt_rising"]:
        return (f"below step 2, and its alpha rose at every halving of the time step ({r['lmgc_dt']}): the finest "
                "step still errs low, a time-step artefact")
    if br == "suspect low":
        return "below step 2: a contradiction (a lower state step 2 missed, or an engine artefact)"
    return "below step 2, within the engine's own bracket slack"


def summary_lines(df) -> list[dict]:
    """The page's opening lines ({"text", "href": scene or None}): how many scenes agree with their
    reference within its tolerance, how many engine results agree with the frictional limit
    analysis within :data:`AGREE`, and one line per result that does not, with its reason
    (:func:`short_reason`) and a link to its scene."""
    n = len(df)
    out = []
    ref = df[[_finite(v) for v in df["ref_alpha"]]] if n else df
    if len(ref):
        ok = [bool(v) for v in ref["within_ref"]]
        out.append({"text": f"Limit analysis: {sum(ok)} of {len(ref)} scenes with a reference agree with it within "
                            "its tolerance.", "href": None})
        out += [{"text": f"limit analysis {_pct(r['nlp_err'])} from its reference ({r['ref_source']})",
                 "href": r["name"]} for (_, r), good in zip(ref.iterrows(), ok) if not good]
    lines, ran, off = [], 0, 0
    for engine, col in (("YADE", "dem"), ("LMGC90", "lmgc")):
        if f"{col}_status" not in df:
            continue
        for _, r in df.iterrows():
            if r.get(f"{col}_status") != "collapsed" or not _finite(r.get(f"{col}_alpha")):
                continue
            ran += 1
            v = r.get(f"{col}_vs_la")
            if _finite(v) and abs(v) > AGREE:
                off += 1
                lines.append({"text": f"{engine} {_pct(v)}: {short_reason(r, col)}", "href": r["name"]})
    if ran:
        out.append({"text": f"Dynamic engines: {ran - off} of {ran} collapses agree with the frictional limit "
                            f"analysis within {100 * AGREE:.0f} %. Theory brackets a rigid-block collapse between "
                            "step 2 (the frictional minimum) and the LP (an upper bound); the others:", "href": None})
        out += lines
    return out


HEAD = ["scene", "dim", "blocks", "joints", "reference", "published", "LP", "NLP", "MILP", "DEM", "LP err", "NLP err",
        "DEM vs LA", "LP s", "NLP s", "DEM s", "similarity", "LMGC90", "LMGC90 vs LA", "LMGC90 s"]


def _flag(text: str, bracket) -> str:
    """A DEM cell with its bracket flag (dem_validation.bracket): '0.182 (suspect low)'."""
    return f"{text} ({bracket})" if isinstance(bracket, str) and bracket else text


def _vs_la(r, col: str) -> str:
    """An engine's alpha against the frictional limit analysis, with the half-width of its own
    bisection bracket: '+0.50 % ± 0.50 %' says that the rigid-block answer is inside it."""
    v, u, f = r.get(f"{col}_vs_la"), r.get(f"{col}_uncertainty"), r.get("fric_alpha")
    if _finite(v) and _finite(u) and _finite(f) and f:
        return f"{_pct(v)} ± {100 * u / f:.2f} %"
    return _pct(v)


def _cells(r):
    def st(alpha, status):
        if status in FAIL:
            return "failed"
        if status == "skipped" and alpha is None:
            return "skipped"
        if status in ("infeasible", "unbounded") and not _finite(alpha):
            return status
        return _num(alpha)

    return [r["name"], str(r["dim"]), _num(r["n_blocks"], "d") if _finite(r["n_blocks"]) else "–",
            _num(r["n_interfaces"], "d") if _finite(r["n_interfaces"]) else "–", _num(r["ref_alpha"]),
            _num(r.get("pub_alpha")),
            st(r["lp_alpha"], r["lp_status"]), st(r["nlp_alpha"], r["nlp_status"]),
            st(r["global_alpha"], r["global_status"]), _flag(st(r["dem_alpha"], r["dem_status"]), r.get("dem_bracket")),
            _pct(r["lp_err"]), _pct(r["nlp_err"]), _vs_la(r, "dem"), _num(r["lp_time_s"], ".2f"),
            _num(r["nlp_time_s"], ".2f"), _num(r["dem_time_s"], ".0f"), _num(r["mech_similarity"], ".2f"),
            _flag(st(r.get("lmgc_alpha"), r.get("lmgc_status")), r.get("lmgc_bracket"))
            if isinstance(r.get("lmgc_status"), str) else "–",
            _vs_la(r, "lmgc"), _num(r.get("lmgc_time_s"), ".0f")]


def _markdown(df, mech_png, stamp, wall_time, cap_png=None, example=()):
    cap_png = cap_png or {}
    lines = ["# Collapse of block masonry: limit analysis against DEM", "",
             f"{stamp}; {len(df)} scenes" + (f"; run time {wall_time:.0f} s" if wall_time else "") + ".", "",
             ] + [f"- {'[' + x['href'] + '](#' + x['href'] + '): ' if x['href'] else ''}{x['text']}"
                  for x in summary_lines(df)] + ["",
             "| " + " | ".join(HEAD) + " |", "|" + " --- |" * len(HEAD)]
    for _, r in df.iterrows():
        cells = _cells(r)
        cells = [f"**{c}**" if c == "failed" else c for c in cells]
        lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "![alpha per scene](figures/alpha.png)", "", "![run time against error](figures/time_error.png)",
              ""] + list(example)
    for _, r in df.iterrows():
        lines += [f"## {r['name']}", ""]
        if r["title"] or r["figure"]:
            lines += [f"_{r['title']} {r['figure']}_", ""]
        lines += [f"- {s}" for s in explain(r)] + [""]
        if mech_png.get(r["name"]):
            lines += [f"![mechanisms]({mech_png[r['name']]})", ""]
        if cap_png.get(r["name"]):
            lines += [f"![pushover curves]({cap_png[r['name']]})", ""]
    return "\n".join(lines) + "\n"
