"""``limit report SCENE.json [--dem yade|lmgc90|both|none] -o DIR``: one scene's page, the same
stages and layout as the catalog's (:mod:`reports.validate`, :mod:`reports.render`).

DIR gets ``<scene>.html`` (plotly's script inlined: the page opens offline on its own), its
Markdown twin ``<scene>.md``, the table ``results.csv``, the PNG figures under ``figures/`` and
the blocks with every motion for ParaView in ``vtk/<scene>.vtk``. The stages are cached like
the catalog's (an unchanged scene is not recomputed; ``--fresh`` ignores the cache). The page
shows the LP and frictional alpha with the route and the checks, the mechanism (interactive,
and as figures), the dynamic pushover curves and alphas judged against the bracket
[frictional alpha, LP], the code check when the scene has a ``demand``, the worst direction
with ``--sweep`` (3D), and the import summary of a scene written by ``limit import``.

Exit status: 0, 1 when a stage failed (the page shows it in red), 2 for a rejected scene.
"""
from __future__ import annotations

import argparse
import datetime as _dt
import json
import sys
import time
from pathlib import Path

#: the stages of each ``--dem`` choice, after the limit analysis's
DEM_STAGES = {"yade": ["dem"], "lmgc90": ["lmgc"], "both": ["dem", "lmgc"], "none": []}


def parser(p: argparse.ArgumentParser | None = None) -> argparse.ArgumentParser:
    """The command's options (on ``p``, a sub-parser of ``limit``, or a new parser)."""
    from .cache import DEFAULT_DIR

    p = p or argparse.ArgumentParser(prog="limit report", description=__doc__.splitlines()[0])
    p.add_argument("scene")
    p.add_argument("-o", "--out", required=True, metavar="DIR", help="folder of the page and its figures")
    p.add_argument("--dem", choices=list(DEM_STAGES), default="both",
                   help="dynamic engines to run (default both: YADE and LMGC90)")
    p.add_argument("--sweep", type=float, nargs="?", const=5.0, default=None, metavar="DEG",
                   help="3D: also sweep the live load's horizontal direction every DEG degrees (default 5)")
    p.add_argument("--cache", default=str(DEFAULT_DIR), help="result cache folder (default .cache/results)")
    p.add_argument("--jobs", type=int, default=None, help="worker processes (default: one per core)")
    p.add_argument("--fresh", action="store_true", help="ignore cached results")
    p.add_argument("--no-progress", action="store_true")
    return p


def run(args) -> int:
    from limit.errors import SceneError
    from limit.model.scene import load_scene, read_json

    from . import render
    from .cache import Cache
    from .validate import collect, failures

    t0 = time.perf_counter()
    src = Path(args.scene)
    data = read_json(src)
    scene = load_scene(data)  # a rejected scene stops here, with its reason (exit 2)
    name = data.get("name", src.stem)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = src
    if args.sweep is not None:
        if data.get("dim") != 3:
            raise SceneError("--sweep: the direction sweep is for 3D scenes (this one is 2D)")
        meta = dict(data.get("meta") or {})
        meta["sweep"] = {"step": float(args.sweep)}
        data = {**data, "meta": meta}
        path = out / f"{name}.scene.json"  # the scene as analysed, with its sweep request
        path.write_text(json.dumps(data, indent=1))
    stages = ["la", "cone", "sweep"] + DEM_STAGES[args.dem]
    done, df = collect([path], stages, Cache(args.cache), fresh=args.fresh, jobs=args.jobs,
                       progress=not args.no_progress, log="report", scenes={name: scene})
    from . import table

    table.write(df, out)
    page = scene_page(df, path, done, out, wall_time=time.perf_counter() - t0, scene=scene)
    bad = failures(done)
    for line in render.scene_summary(df.iloc[0], done.get((name, "la"))):
        print(f"report: {line}", file=sys.stderr)
    print(f"report: wrote {page} ({page.stat().st_size / 1e6:.1f} MB)", file=sys.stderr)
    for scene, stage, why in bad:
        print(f"report: FAILED {scene} {stage}: {why}", file=sys.stderr)
    if not len(df) or not any(done.get((name, s)) for s in stages):
        raise SceneError(f"{src}: no stage ran")
    return 1 if bad else 0


def scene_page(df, path: Path, results: dict, out: Path, wall_time: float | None = None, scene=None) -> Path:
    """Write ``<scene>.html`` and ``<scene>.md`` into ``out``; returns the HTML path. ``scene``: the
    file's loaded scene, where the caller has it."""
    from limit.model.scene import read_json

    from . import render, verdict, view3d, worst_direction

    data = read_json(path)
    name = data.get("name", Path(path).stem)
    r = df.iloc[0]
    s = render._scene_figures(name, Path(path), df, results, out, scene=scene)
    s.update(explain=render.explain(r), subtitle=render._subtitle(r))
    lines = []
    la = results.get((name, "la")) or {}
    if (la.get("verdict") or {}).get("status"):
        lines += ["## Code check of the local mechanism"] + verdict.scene_lines(name, data.get("dim"), la["verdict"])
    try:
        lines += worst_direction.section(results, {name: Path(path)}, out / "figures")
    except Exception as exc:  # noqa: BLE001 - noted, never fatal
        lines += [f"Worst load direction: the section could not be made ({type(exc).__name__}: {exc})."]
    lines += import_lines((data.get("meta") or {}).get("import"))
    s["blocks"] = render.md_blocks(lines)
    stamp = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    page = render.render("scene.html", title=f"{name}: limit analysis against DEM", stamp=stamp, wall_time=wall_time,
                         legend=render.LEGEND.split(" Blocks and")[0] + f" Blocks and motions for ParaView: "
                                                                         f"vtk/{name}.vtk; the table: results.csv.",
                         **(view3d.script() if s["views"] else {}), summary=[{"text": t, "href": None} for t in render.scene_summary(r, la)],
                         head=render.HEAD, rows=render._rows(df), scenes=[s])
    html_path = out / f"{name}.html"
    html_path.write_text(page)
    md = [f"# {name}: limit analysis against DEM", ""] + [f"- {x}" for x in render.scene_summary(r, la)] + [""]
    md += [f"- {x}" for x in s["explain"]] + [""]
    md += [f"![mechanisms]({s['mech_png']})", ""] if s["mech_png"] else []
    md += [f"![pushover curves]({s['cap_png']})", ""] if s["cap_png"] else []
    (out / f"{name}.md").write_text("\n".join(md + lines) + "\n")
    return html_path


def import_lines(meta: dict | None) -> list[str]:
    """Markdown lines of ``meta.import`` (written by ``limit import``): what was read and repaired."""
    if not meta:
        return []
    files = ", ".join(Path(f).name for f in meta.get("files") or [])
    out = ["## Import", f"- From {files} (units {meta.get('units', 'm')}, {meta.get('dim')}D): {meta.get('blocks')} "
                        f"blocks, {meta.get('hulls')} convex hulls, {meta.get('compound_blocks')} compound blocks of "
                        f"{meta.get('parts')} parts; {meta.get('interfaces')} interfaces; mass "
                        f"{meta.get('mass_kg', float('nan')):.6g} kg; fixed: {meta.get('fixed')}."]
    gap, over = meta.get("largest_gap_closed_m"), meta.get("largest_overlap_closed_m")
    if gap is not None or over is not None:
        out.append(f"- Joints snapped to their mid-plane: {meta.get('joints_snapped')}; largest gap closed "
                   f"{1e3 * (gap or 0):.3g} mm, largest overlap closed {1e3 * (over or 0):.3g} mm; largest corner move "
                   f"{1e3 * (meta.get('largest_corner_move_m') or 0):.3g} mm.")
    for w in meta.get("warnings") or []:
        out.append(f"- Warning: {w}")
    return out


def main(argv=None) -> int:
    from limit.errors import run_command

    args = parser().parse_args(argv)
    return run_command(lambda: run(args), debug_env="LIMIT_DEBUG")


if __name__ == "__main__":
    sys.exit(main())
