"""The results table: one row per catalog scene, written as CSV and Parquet through pandas.

Columns (alpha values dimensionless, times in seconds):

* scene facts: ``name``, ``title``, ``figure``, ``dim``, ``n_blocks``, ``n_free``, ``n_interfaces``;
* ``notes``: the scene's ``meta.notes``;
* a published value (``meta.published``, shown beside ours, not a pass/fail reference):
  ``pub_alpha`` (None where the publication gives no number), ``pub_kind``, ``pub_source``,
  ``pub_note`` (why ours differs), ``pub_diff`` (ours - published, relative; ours = the
  frictional value, or the LP one where the publication's is an LP value);
* the reference: ``ref_alpha`` and ``ref_kind`` (which collapse factor it is:
  ``alpha`` frictional, ``alpha_lp`` associative, ``alpha_nlp``), ``ref_rtol``, ``ref_source``;
* per method: ``lp_*``, ``nlp_*``, ``global_*`` (MILP), ``iter_*`` (iterative LP),
  ``dem_*``: ``status``, ``alpha``, ``time_s``, ``reason``;
* ``fric_alpha``: the lowest verified frictional value found (NLP, MILP, or in 2D step 2 from a
  DEM collapse state, :mod:`reports.dem_starts`); ``fric_alpha_step2`` without the last;
* ``dstart_alpha``, ``dstart_from``, ``dstart_tried``: step 2 from the engines' collapse states
  where they collapsed below it (the adopted alpha, the engines it came from, every try);
* errors relative to the reference: ``lp_err``, ``nlp_err``, ``dem_err``, and
  ``dem_vs_la`` (DEM against the frictional limit analysis);
* ``lmgc_*``: the LMGC90 run (rigid contacts), as ``dem_*``, with ``lmgc_err``,
  ``lmgc_vs_la`` and ``lmgc_similarity`` (all empty when LMGC90 did not run), and
  ``lmgc_creep`` (a trial that held never came to rest by speed: its blocks crept through the hold
  or rattled in place), ``lmgc_dt`` (each time step's alpha and whether they converged:
  :func:`dt_text`) and ``lmgc_dt_rising`` (its alpha rose at every halving of the time step:
  :func:`dem_validation.bracket.rising_with_dt`);
* ``cone_*``: the limit analysis of a 3D scene with 24 inscribed sliding faces (a
  near-circular friction cone, as in both dynamic engines): ``cone_status``,
  ``cone_lp_alpha``, ``cone_alpha`` (frictional: NLP, or step 2 from a DEM collapse state;
  ``cone_alpha_step2`` without it), ``cone_time_s``, and
  ``dem_vs_cone``, ``lmgc_vs_cone``; empty in 2D, where two faces are exact;
* ``dem_bracket``, ``lmgc_bracket``: "suspect low" / "suspect high" where the engine's alpha lies
  below the frictional limit analysis or above the LP (the cone's in 3D) by more than 1 %
  (:mod:`dem_validation.bracket`), else empty; in 3D a run suspect low is judged again on point
  contacts at the joints' corners where step 2 from an engine's state verifies a lower point
  there (``pc_alpha``, ``pc_lp_alpha``, ``pc_from``: that point, its LP and the engine whose
  state it came from; ``dem_bracket_model``, ``lmgc_bracket_model``: the joint model judged on);
* ``mech_similarity``: the cosine between the limit-analysis mechanism and the
  DEM motion, compared through the velocities of every block vertex
  (scale-free: 1 = the same motion, 0 = unrelated).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from limit.model.dims import rigid_velocity
from limit.results.summary import global_interval


def vertex_motion(scene, per_block: dict) -> np.ndarray:
    """Velocities of all free-block vertices (flattened) of a per-block rigid motion."""
    d = scene.dim
    out = []
    for i in scene.free:
        b = scene.blocks[i]
        m = per_block.get(b.id)
        if m is None:
            return None
        out.append(rigid_velocity(m, b.poly.vertices - b.centroid, d).ravel())
    return np.concatenate(out) if out else None


def similarity(scene, a: dict | None, b: dict | None) -> float:
    """Cosine between two rigid-block motions (nan when one is missing or zero)."""
    if not a or not b:
        return float("nan")
    va, vb = vertex_motion(scene, a), vertex_motion(scene, b)
    if va is None or vb is None:
        return float("nan")
    na, nb = np.linalg.norm(va), np.linalg.norm(vb)
    if na == 0 or nb == 0 or not np.isfinite(na * nb):
        return float("nan")
    return float(va @ vb / (na * nb))


def _rel(a, ref):
    if a is None or ref is None or not np.isfinite(ref) or ref == 0:
        return float("nan")
    return (a - ref) / abs(ref)


def la_mechanism(la: dict):
    nlp = la.get("nlp") or {}
    if nlp.get("status") == "optimal" and nlp.get("mechanism"):
        return nlp["mechanism"], "nlp"
    lp = la.get("lp") or {}
    return lp.get("mechanism"), "lp"


def dem_model_text(dem: dict) -> str:
    """One sentence on the DEM's contact model, its runs and how it treats the rounding."""
    runs = [r for r in dem.get("runs") or [] if r.get("alpha") is not None]
    if not runs:
        return ""
    raw = ", ".join(f"{r['alpha']:.4g} at eps {r['eps']:.2g}" for r in runs)
    if dem.get("contact", "vertex") == "vertex":
        radii = ", ".join(f"{1e3 * r['sphere_radius']:.3g}" for r in runs if r.get("sphere_radius"))
        pen = dem.get("penetration_ratio")
        extrapolated = (dem.get("extrapolation") or {}).get("method", "richardson") == "richardson"
        rounding = ("r scales with eps, so the extrapolation to eps = 0 also removes the corner rounding: the DEM "
                    "alpha is corrected for the rounding, not compared with a rounded geometry" if extrapolated else
                    "the stiffest run's alpha is taken as it is, with its corner rounding of r")
        return (f"Vertex-to-face model: runs {raw}; vertex spheres r = {radii} mm ({rounding})"
                + (f"; deepest contact at an equilibrium {pen:.2f} r" if pen is not None else "") + "."
                + (f" {dem['note'][0].upper()}{dem['note'][1:]}." if dem.get("note") else "")
                + (f" No stiffer run: {dem['refinement']}." if dem.get("refinement") else ""))
    return f"Polyhedra model: runs {raw}, extrapolated to rigid contacts as eps^1/3."


def dt_text(lm: dict) -> str:
    """LMGC90's alphas at its halved time steps: '1e-3 s: 0.1332, 5e-4 s: 0.1419 (converged)'; empty
    for a run at one time step."""
    runs = [r for r in lm.get("runs") or [] if r.get("dt") is not None and r.get("alpha") is not None]
    if len(runs) < 2:
        return ""
    return (", ".join(f"{r['dt']:.2g} s: {r['alpha']:.4g}" for r in runs)
            + {True: " (converged)", False: " (not converged)"}.get(lm.get("dt_converged"), ""))


def row(path: Path, la: dict | None, dem: dict | None, lmgc: dict | None = None, cone: dict | None = None,
        dem_start: list | None = None, scene=None) -> dict:
    """One scene's row of the results table; ``scene``: the file's loaded scene, when the caller
    has it (loading a scene of many parts takes seconds)."""
    from limit.model.scene import load_scene

    from dem_validation.bracket import rising_with_dt

    from .dem_starts import adopted_alpha

    data = json.loads(Path(path).read_text())
    meta = data.get("meta") or {}
    exp = data.get("expected") or {}
    la = la or {}
    lp = la.get("lp") or {}
    nlp = la.get("nlp") or {}
    g = nlp.get("global") or {}
    it = nlp.get("iterative_lp") or {}
    r = {"name": data.get("name", path.stem), "title": meta.get("title", ""), "figure": meta.get("figure", ""),
         "dim": data.get("dim"), "n_blocks": la.get("n_blocks"), "n_free": la.get("n_free_blocks"),
         "n_interfaces": la.get("n_interfaces")}
    ref_kind = next((k for k in ("alpha", "alpha_nlp", "alpha_lp") if exp.get(k) is not None), None)
    r.update(ref_alpha=exp.get(ref_kind) if ref_kind else None, ref_kind=ref_kind, ref_rtol=exp.get("rtol"),
             ref_source=exp.get("source", ""))
    pub = meta.get("published") or {}
    r.update(notes=meta.get("notes", ""), pub_alpha=pub.get("alpha"), pub_kind=pub.get("kind", ""),
             pub_source=pub.get("source", ""), pub_note=pub.get("note", ""))
    r.update(lp_status=lp.get("status"), lp_alpha=lp.get("alpha"), lp_time_s=lp.get("time_s"),
             lp_reason=lp.get("reason", ""))
    r.update(nlp_status=nlp.get("status"), nlp_alpha=nlp.get("alpha"), nlp_time_s=nlp.get("time_s"),
             nlp_reason=nlp.get("reason", ""), nlp_arbitrary_alpha=nlp.get("alpha_arbitrary_start"))
    r.update(global_status=g.get("status"), global_alpha=g.get("alpha"), global_time_s=g.get("time_s"),
             iter_status=it.get("status"), iter_alpha=it.get("alpha"))
    r["global_lo"], r["global_hi"] = global_interval(nlp) or (None, None)
    fric = [a for a in (nlp.get("alpha") if nlp.get("status") in ("optimal", "skipped") else None,
                        g.get("alpha") if g.get("status") in ("optimal", "time_limit") else None) if a is not None]
    r["fric_alpha"] = r["fric_alpha_step2"] = min(fric) if fric else None
    ds = adopted_alpha(dem_start)
    r["dstart_alpha"] = ds
    r["dstart_from"] = ", ".join(e["engine"] for e in dem_start or [] if e.get("adopted"))
    r["dstart_tried"] = ", ".join(f"{e['engine']}: {e['alpha']:.5g}" if e.get("alpha") is not None else
                                  f"{e['engine']}: {e.get('reason', '')}" for e in dem_start or [])
    if ds is not None and data.get("dim") != 3:
        r["fric_alpha"] = min(ds, r["fric_alpha"]) if r["fric_alpha"] is not None else ds
    dem = dem or {}
    r.update(dem_status=dem.get("status"), dem_alpha=dem.get("alpha"), dem_time_s=dem.get("time_s"),
             dem_reason=dem.get("reason", dem.get("note", "")), dem_uncertainty=dem.get("alpha_uncertainty"),
             dem_dead=bool(dem.get("dead_load_collapse")), dem_model=dem_model_text(dem))
    # The LP is compared with alpha_lp, or with the frictional alpha where the NLP found the LP
    # mechanism frictional already (skipped).
    lp_ref = exp.get("alpha_lp")
    if lp_ref is None and nlp.get("status") == "skipped":
        lp_ref = exp.get("alpha")
    r["lp_err"] = _rel(r["lp_alpha"], lp_ref)
    fric_ref = exp.get("alpha_nlp", exp.get("alpha"))
    r["nlp_err"] = _rel(r["fric_alpha"], fric_ref)
    r["dem_err"] = _rel(r["dem_alpha"], exp.get("alpha"))
    r["dem_vs_la"] = _rel(r["dem_alpha"], r["fric_alpha"])
    ours = r["lp_alpha"] if r["pub_kind"] == "LP" else (nlp.get("alpha_arbitrary_start") if "arbitrary"
                                                          in r["pub_kind"] else r["fric_alpha"])
    r["pub_diff"] = _rel(ours, r["pub_alpha"])
    r["within_ref"] = (abs(r["nlp_err"]) <= (r["ref_rtol"] or 0) + 1e-12) if np.isfinite(r["nlp_err"]) else None
    lm = lmgc or {}
    r.update(lmgc_status=lm.get("status"), lmgc_alpha=lm.get("alpha"), lmgc_time_s=lm.get("time_s"),
             lmgc_reason=lm.get("reason", lm.get("note", "")), lmgc_uncertainty=lm.get("alpha_uncertainty"),
             lmgc_dead=bool(lm.get("dead_load_collapse")), lmgc_dt=dt_text(lm), lmgc_dt_rising=rising_with_dt(lm),
             lmgc_creep=any(h.get("outcome") == "stable" and h.get("settled", "speed" if h.get("rest") else None)
                            != "speed" for h in lm.get("history") or []))
    r["lmgc_err"] = _rel(r["lmgc_alpha"], exp.get("alpha"))
    r["lmgc_vs_la"] = _rel(r["lmgc_alpha"], r["fric_alpha"])
    cl, cn = (cone or {}).get("lp") or {}, (cone or {}).get("nlp") or {}
    r.update(cone_status=cn.get("status") or cl.get("status"), cone_lp_alpha=cl.get("alpha"),
             cone_alpha=cn.get("alpha") if cn.get("status") in ("optimal", "skipped") else None,
             cone_time_s=(cone or {}).get("stage_time_s"))
    r["cone_alpha_step2"] = r["cone_alpha"]
    if ds is not None and data.get("dim") == 3:
        r["cone_alpha"] = min(ds, r["cone_alpha"]) if r["cone_alpha"] is not None else ds
    from dem_validation.bracket import cone_lp_factor, judge, label, on_point_contacts

    three = data.get("dim") == 3
    la_br = {"fric_alpha": r["cone_alpha"] if three else r["fric_alpha"],
             "lp_alpha": r["cone_lp_alpha"] if three else r["lp_alpha"], "lp_factor": cone_lp_factor(3 if three else 2)}
    pc = point_contacts(dem_start) if three else None
    r.update(pc_alpha=(pc or {}).get("alpha"), pc_lp_alpha=(pc or {}).get("lp_alpha"),
             pc_from=(pc or {}).get("engine", ""))
    for key, res in (("dem", dem), ("lmgc", lm)):
        entry = judge(res, la_br)
        if pc is not None and entry["verdict"] == "suspect" and entry["side"] == "low":
            entry = on_point_contacts(res, entry, pc)
        r[f"{key}_bracket"] = label(entry)
        r[f"{key}_bracket_model"] = entry.get("model", "")
    r["dem_vs_cone"] = _rel(r["dem_alpha"], r["cone_alpha"])
    r["lmgc_vs_cone"] = _rel(r["lmgc_alpha"], r["cone_alpha"])
    mech, kind = la_mechanism(la)
    r["mech_kind"] = kind
    try:
        scene = scene if scene is not None else load_scene(data)
        r["mech_similarity"] = similarity(scene, mech, dem.get("displacement"))
        r["lmgc_similarity"] = similarity(scene, mech, lm.get("displacement"))
    except Exception:  # noqa: BLE001 - a rejected scene has no mechanism to compare
        r["mech_similarity"] = r["lmgc_similarity"] = float("nan")
    return r


def point_contacts(entries) -> dict | None:
    """The lowest verified point-contact state of a scene's DEM starts (:mod:`reports.dem_starts`:
    each engine's ``point_contacts``, with ``engine`` added), else the first tried (None: none)."""
    tried = [{**e["point_contacts"], "engine": e.get("engine", "")} for e in entries or [] if e.get("point_contacts")]
    verified = [t for t in tried if t.get("alpha") is not None]
    return min(verified, key=lambda t: t["alpha"]) if verified else (tried[0] if tried else None)


def results_table(files, results: dict, with_dem: bool = True, with_lmgc: bool = False,
                  dem_start: dict | None = None, scenes: dict | None = None) -> pd.DataFrame:
    """One row per scene file from the stage ``results`` ({(scene, stage): result}) and the DEM
    starts ({scene: entries}, :func:`reports.dem_starts.run`); ``scenes``: {name: loaded scene}
    of those already loaded."""
    rows = []
    for path in files:
        name = json.loads(Path(path).read_text()).get("name", Path(path).stem)
        rows.append(row(Path(path), results.get((name, "la")), results.get((name, "dem")) if with_dem else None,
                        results.get((name, "lmgc")) if with_lmgc else None, results.get((name, "cone")),
                        (dem_start or {}).get(name), (scenes or {}).get(name)))
    return pd.DataFrame(rows)


def write(df: pd.DataFrame, out: Path) -> None:
    """results.csv and results.parquet in ``out`` (each written atomically)."""
    import os
    import tempfile

    for suffix, fn in ((".csv", lambda p: df.to_csv(p, index=False)), (".parquet", lambda p: df.to_parquet(p))):
        fd, tmp = tempfile.mkstemp(dir=out, suffix=suffix)
        os.close(fd)
        fn(tmp)
        os.replace(tmp, out / f"results{suffix}")


#: (column, heading, format) of the engines table: LA against YADE against LMGC90
ENGINE_COLUMNS = [
    ("name", "scene", "{}"), ("dim", "dim", "{}"), ("n_free", "free blocks", "{:.0f}"),
    ("lp_alpha", "LA: LP", "{:.5g}"), ("fric_alpha", "LA: frictional", "{:.5g}"),
    ("cone_alpha", "LA, 24-face cone: frictional", "{:.5g}"),
    ("dem_alpha", "YADE", "{:.5g}"), ("dem_vs_la", "YADE vs LA", "{:+.2%}"), ("dem_time_s", "YADE s", "{:.0f}"),
    ("lmgc_alpha", "LMGC90", "{:.5g}"), ("lmgc_vs_la", "LMGC90 vs LA", "{:+.2%}"),
    ("lmgc_time_s", "LMGC90 s", "{:.0f}"),
]


def contradictions(df: pd.DataFrame, step2_only: bool = False) -> list[tuple]:
    """(scene, engine, dynamic alpha, frictional alpha, relative gap) of every dynamic collapse below
    the frictional limit analysis by more than :data:`reports.dem_starts.SLACK`: the 24-face cone's
    in 3D, the paper model's in 2D, or on point contacts where the run was judged on them
    (``*_bracket_model``). ``step2_only``: against step 2's own alpha (before the DEM starts and
    point contacts)."""
    from dem_validation.bracket import POINT_CONTACTS

    from .dem_starts import below

    def number(v):
        return None if v is None or (isinstance(v, float) and not np.isfinite(v)) else float(v)

    out = []
    for _, r in df.iterrows():
        col = ("cone_alpha" if r.get("dim") == 3 else "fric_alpha") + ("_step2" if step2_only else "")
        for key, engine in (("dem", "YADE"), ("lmgc", "LMGC90")):
            on_pc = not step2_only and r.get(f"{key}_bracket_model") == POINT_CONTACTS
            fric = number(r.get("pc_alpha" if on_pc else col))
            a = number(r.get(f"{key}_alpha"))
            if r.get(f"{key}_status") == "collapsed" and below(a, fric):
                out.append((r["name"], engine + (" (point contacts)" if on_pc else ""), a, fric, a / fric - 1.0))
    return out


def contradictions_markdown(df: pd.DataFrame) -> str:
    """A few lines: how many dynamic results lie below the frictional limit analysis, before and
    after the DEM starts and the point-contact check, which runs were judged on point contacts,
    and which results stay below."""
    from dem_validation.bracket import POINT_CONTACTS

    before, after = contradictions(df, step2_only=True), contradictions(df)
    n = int(sum((df.get(f"{k}_status") == "collapsed").sum() for k in ("dem", "lmgc") if f"{k}_status" in df))
    lines = [f"Dynamic collapses below the frictional limit analysis (by more than 1 %): {len(after)} of {n} "
             f"collapsed engine results ({len(before)} against step 2 before the DEM starts)."]
    adopted = df[df["dstart_from"].astype(bool)] if "dstart_from" in df else df.iloc[0:0]
    for _, r in adopted.iterrows():
        lines.append(f"- {r['name']}: step 2 from the {r['dstart_from']} collapse state verified {r['dstart_alpha']:.5g}.")
    for _, r in df.iterrows():
        judged = [e for k, e in (("dem", "YADE"), ("lmgc", "LMGC90")) if r.get(f"{k}_bracket_model") == POINT_CONTACTS]
        if judged:
            lines.append(f"- {r['name']}: {' and '.join(judged)} judged on point contacts at the joints' corners, as "
                         f"the engines carry them: step 2 from the {r['pc_from']} state verified {r['pc_alpha']:.5g}, "
                         f"the LP {r['pc_lp_alpha']:.5g}.")
    for name, engine, a, fric, gap in after:
        lines.append(f"- {name}: {engine} {a:.5g} against {fric:.5g} ({gap:+.1%})")
    return "\n".join(lines) + "\n"


def engines_markdown(df: pd.DataFrame) -> str:
    """The catalog as one markdown table: the limit analysis (the paper's friction model,
    and the near-circular cone in 3D) against YADE and LMGC90, with their wall times (s).
    A stage without a number shows its status (dead-load collapse, skipped, failed). The
    contradiction count (:func:`contradictions_markdown`) comes first."""
    def cell(r, col, fmt):
        v = r.get(col)
        if v is None or (isinstance(v, float) and not np.isfinite(v)):
            st = {"lp_alpha": "lp", "fric_alpha": "nlp", "cone_alpha": "cone", "dem_alpha": "dem",
                  "lmgc_alpha": "lmgc"}.get(col)
            if st and r.get(f"{st}_dead"):
                return "dead-load collapse"
            return str(r.get(f"{st}_status") or "-") if st else "-"
        text = fmt.format(v)
        flag = r.get({"dem_alpha": "dem_bracket", "lmgc_alpha": "lmgc_bracket"}.get(col, ""))
        return f"{text} ({flag})" if isinstance(flag, str) and flag else text

    head = "| " + " | ".join(h for _, h, _ in ENGINE_COLUMNS) + " |"
    lines = [contradictions_markdown(df), head, "|" + " --- |" * len(ENGINE_COLUMNS)]
    for _, r in df.iterrows():
        lines.append("| " + " | ".join(cell(r, c, f) for c, _, f in ENGINE_COLUMNS) + " |")
    return "\n".join(lines) + "\n"
