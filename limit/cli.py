"""Command line: ``limit info|solve|check|sweep SCENE.json [--json OUT.json]``, ``limit import FILE... -o SCENE.json``,
``limit build KIND ... -o SCENE.json``, ``limit report SCENE.json -o DIR`` and ``limit settings`` (or ``python -m limit``).

Exit status (docs/formats.md, 'Commands'): 0 success, 2 rejected input (one line on
stderr, no traceback), 1 any other failure, 130 interrupted.
"""
from __future__ import annotations

import argparse
import logging
import os
import sys

from limit.errors import SceneError, run_command
from limit.solve.solvers import SOLVERS
from limit.solve.status import CheckStatus

#: the registry's names (limit.solve.solvers imports no cvxpy, which is slow to import for `info`)
LP_SOLVERS = list(SOLVERS)


def _parser() -> argparse.ArgumentParser:
    from limit import __version__
    p = argparse.ArgumentParser(prog="limit", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    pi = sub.add_parser("info", help="check a scene and print its counts, mass and bounding box")
    pi.add_argument("scene")
    pi.add_argument("--json", metavar="OUT.json", help="also write the summary as JSON")
    pi.add_argument("--strict", action="store_true", help="an unknown key in the scene is an error (exit 2)")
    ps = sub.add_parser("solve", help="limit analysis: the collapse load factor and mechanism")
    ps.add_argument("scene")
    ps.add_argument("--strict", action="store_true", help="an unknown key in the scene is an error (exit 2)")
    ps.add_argument("--method", choices=["lp", "nlp", "auto"], default="auto",
                    help="lp: associative bound only; nlp: LP then the frictional NLP; auto (default): NLP only where needed")
    ps.add_argument("--json", metavar="OUT.json", help="write the result file (docs/formats.md)")
    ps.add_argument("--plot", metavar="OUT.png|DIR", help="draw the mechanism (into a folder also as an interactive "
                                                         "page): the collapse mechanisms, or for a scene "
                                                     "that collapses under its dead load, the dead-load mechanism")
    ps.add_argument("--solver", choices=LP_SOLVERS, default="auto",
                    help="LP solver (default auto: the structured interior point method 'ipm' from 3,000 "
                         "block unknowns on (setting lp_ipm_min_dof), clarabel below); a failed check falls "
                         "back to another")
    ps.add_argument("--no-fallback", action="store_true", help="do not retry a failed LP with another solver")
    ps.add_argument("--model", choices=["paper", "vertex"], default="paper",
                    help="interface model: paper's yield domain (default) or point contacts at the vertices")
    ps.add_argument("--slide-faces", type=int, default=None, metavar="K",
                    help="sliding faces per 3D interface (even, >= 4; 4 = the paper's two directions); default: "
                         "the scene's interfaces.sliding_faces, else 24 (inscribed, within 0.86 %% of the Coulomb cone)")
    ps.add_argument("--slide-fit", choices=["auto", "circumscribed", "inscribed"], default="auto",
                    help="friction polygon around (paper) or inside the friction circle; auto: paper for 4 faces, inscribed above")
    ps.add_argument("--check-kinematic", action="store_true",
                    help="also solve the kinematic LP and record its alpha (duality check)")
    ps.add_argument("--nlp-solver", choices=["auto", "slsqp", "sla"], default="auto",
                    help="step 2 solver: SLSQP (small problems) or successive LP; auto picks by size")
    ps.add_argument("--global", dest="global_check", action="store_true",
                    help="also compute the global frictional minimum by mixed-integer LP (scenes up to 30 free "
                         "blocks, setting global_max_blocks); a point of it below step 2's alpha that passes "
                         "the check becomes the answer")
    ps.add_argument("--global-time-limit", type=float, default=None, metavar="S",
                    help="wall-clock limit of that MILP in s (default 120, setting global_time_limit); at the "
                         "limit its best point so far counts")
    ps.add_argument("--iterative-lp", action="store_true",
                    help="also run the iterative LP of Gilbert, Casapulla & Ahmed (2006)")
    ps.add_argument("--arbitrary-start", action="store_true",
                    help="also run the NLP from an arbitrary start (the paper's Fig. 4 comparison)")
    ps.add_argument("--nlp-time-budget", type=float, default=None, metavar="S",
                    help="wall-clock budget of step 2 in s: no restart begins after it (default 120, setting "
                         "nlp_time_budget)")
    ps.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a setting (repeatable): a route threshold, time budget or check tolerance; "
                         "'limit settings' lists them with their defaults")
    ps.add_argument("--no-cache", action="store_true",
                    help="solve again even when the result cache holds this scene with these options "
                         "(also: the environment variable LIMIT_NO_CACHE=1)")
    ps.add_argument("--cache", metavar="DIR", default=None, help="result cache folder (default .cache/results)")
    ps.add_argument("--dem-start", metavar="DEM.json", default=None,
                    help="also start step 2 from a DEM run's collapse state (its result file, python -m "
                         "dem_validation run --json): the joints it opens and slides as the piece LP's flowing "
                         "faces; a verified point below step 2's alpha becomes the answer")
    pc = sub.add_parser("check", help="code check of the local mechanism: M*, e*, a0*, capacity curve, verdict "
                                      "(NTC 2018 / Circolare C8.7.1)")
    pc.add_argument("scene")
    pc.add_argument("--strict", action="store_true", help="an unknown key in the scene is an error (exit 2)")
    pc.add_argument("--method", choices=["lp", "nlp", "auto"], default="auto", help="as for solve")
    pc.add_argument("--fc", type=float, default=None,
                    help="confidence factor FC (default: the scene's demand.fc, else 1.35, knowledge level LC1)")
    pc.add_argument("--ag", type=float, default=None, metavar="G",
                    help="peak ground acceleration on rock, in g: with it, the check against this demand (the "
                         "spectrum options below) instead of the scene's own 'demand', if any")
    pc.add_argument("--F0", type=float, default=None, help="spectral amplification (default 2.5; required with --Tc-star)")
    pc.add_argument("--Tc-star", type=float, default=None, metavar="S",
                    help="Tc* of the limit state (s): with it S, TB, TC and TD come from the site (NTC 2018 "
                         "3.2.3.2.1: --soil, --topography); an explicit --S, --TB, --TC or --TD overrides one")
    pc.add_argument("--soil", default=None, choices=["A", "B", "C", "D", "E"],
                    help="subsoil category, with --Tc-star (default A): SS and CC of NTC 2018 Table 3.2.IV")
    pc.add_argument("--topography", default=None, choices=["T1", "T2", "T3", "T4"],
                    help="topographic category, with --Tc-star (default T1): ST of NTC 2018 Table 3.2.V")
    pc.add_argument("--topography-ratio", type=float, default=None, metavar="R",
                    help="the site's height above the relief's base over the relief's height (default 1: the top)")
    for k, v, h in (("S", 1.0, "soil and topography factor"), ("TB", 0.15, "corner period TB (s)"),
                    ("TC", 0.5, "corner period TC (s)"), ("TD", 2.0, "corner period TD (s)")):
        pc.add_argument(f"--{k}", type=float, default=None, help=f"{h} (default {v:g}, or the site's with --Tc-star)")
    for k, v, h in (("q", 2.0, "behaviour factor"), ("Z", 0.0, "height of the mechanism's base (m; 0: ground level)")):
        pc.add_argument(f"--{k}", type=float, default=v, help=f"{h} (default {v:g})")
    pc.add_argument("--sld-ag", type=float, default=None, metavar="G",
                    help="the damage limit state's ag on rock (g): adds the linear SLD check (Circolare 617/2009 "
                         "C8A.4.2.3); its spectrum from --sld-F0 and --sld-Tc-star with the site, else --S")
    pc.add_argument("--sld-F0", type=float, default=None, help="spectral amplification at SLD")
    pc.add_argument("--sld-Tc-star", type=float, default=None, metavar="S", help="Tc* at SLD (s)")
    pc.add_argument("--H", type=float, default=None, help="building height (m), with Z > 0")
    pc.add_argument("--N", type=int, default=None, help="storeys, with Z > 0")
    pc.add_argument("--T1", type=float, default=None, help="building's first period (s), with Z > 0")
    pc.add_argument("--xi1", type=float, default=0.05,
                    help="building's first-mode damping ratio, a fraction (default 0.05; 0.10-0.20 for a masonry "
                         "building at the ultimate state): the floor spectrum of the nonlinear check above ground")
    pc.add_argument("--xi-mech", type=float, default=0.08,
                    help="mechanism's damping ratio at SLV, a fraction (default 0.08): nonlinear check above ground")
    pc.add_argument("--json", metavar="OUT.json", help="write the assessment as JSON")
    pc.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a setting (repeatable), as for solve: e.g. curve_steps, curve_time_budget")
    pw = sub.add_parser("sweep", help="3D: alpha over the horizontal directions of the live load, its minimum")
    pw.add_argument("scene")
    pw.add_argument("--step", type=float, default=5.0, help="degrees between directions (default 5)")
    pw.add_argument("--mirror", action="store_true",
                    help="the scene is mirror-symmetric about the vertical plane of its live load (checked): solve "
                         "half; a scene declaring \"symmetry\": \"mirror\" gets this without the option")
    pw.add_argument("--jobs", type=int, default=None, help="local Dask worker processes (default: one per core)")
    pw.add_argument("--scheduler", default=os.environ.get("DASK_SCHEDULER_ADDRESS"),
                    help="address of an existing Dask scheduler (default: a local cluster)")
    pw.add_argument("--json", metavar="OUT.json", help="write alpha(theta) as JSON")
    pw.add_argument("--frictional", action="store_true",
                    help="step 2 at every direction too (default: at the LP's minimum only): the frictional worst direction")
    pw.add_argument("--plot", metavar="OUT.png", help="draw alpha(theta) as a polar plot")
    pw.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a setting (repeatable) in every direction's analysis, as for solve")
    pim = sub.add_parser("import", help="write a scene from CAD or mesh files (OBJ, STL, PLY, DXF)")
    from scenes.importers.command import add_arguments as import_arguments
    import_arguments(pim)
    from reports.scene_report import parser as report_parser

    report_parser(sub.add_parser("report", help="one scene's HTML report: limit analysis, DEM engines, mechanism"))
    pd = sub.add_parser("design", help="tie design: the least total tie capacity at which the frictional alpha "
                                       "reaches a target")
    pd.add_argument("scene")
    pd.add_argument("--target-alpha", type=float, default=None, metavar="A",
                    help="the collapse multiplier to reach; default: the alpha at which the code check of the "
                         "scene's 'demand' passes (its linear SLV and SLD checks)")
    cg = pd.add_mutually_exclusive_group()
    cg.add_argument("--candidates", default=None, metavar="FILE",
                    help="a JSON list of candidate ties (the scene's tie format; a 'capacity' is an upper bound); "
                         "default: the scene's own 'ties'")
    cg.add_argument("--wall-to-wall", nargs=2, default=None, metavar=("TAG_A", "TAG_B"),
                    help="generate the candidates: at each --levels height, a tie between every block tagged "
                         "TAG_A and every block tagged TAG_B that the level cuts ('*': any block; "
                         "limit/tie_candidates.py)")
    pd.add_argument("--levels", type=float, nargs="+", default=None, metavar="Z",
                    help="heights of the generated candidates, in the scene's units (default: mid-height of "
                         "TAG_A's top course)")
    pd.add_argument("--method", choices=["lp", "nlp", "auto"], default="auto",
                    help="the analysis that checks each trial (default auto: step 2 where it can change the answer)")
    pd.add_argument("--dem", action="store_true", help="check the designed scene with YADE's pushover (slow)")
    pd.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a setting (repeatable) in every trial's analysis, as for solve")
    pd.add_argument("-o", "--output", default=None, metavar="OUT.json", help="write the designed scene here")
    pd.add_argument("--json", default=None, metavar="OUT.json", help="write the design's record here")
    sub.add_parser("settings", help="list the settings (limit solve --set NAME=VALUE): default, unit, meaning")
    pb = sub.add_parser("build", help="write a scene of a generated structure (arch, wall, vault, dome)")
    from scenes.generators.command import add_arguments as build_arguments
    build_arguments(pb)
    return p


def cmd_import(args) -> int:
    from scenes.importers.command import run
    return run(args)


def cmd_build(args) -> int:
    from scenes.generators.command import run
    return run(args)


def cmd_check(args) -> int:
    from limit import jsonio
    from limit.analysis import analyse
    from limit.verdict.local_check import format_assessment, verdict
    from limit.model.scene import load_scene
    from limit.model.seismic_demand import from_mapping

    if args.fc is not None and not (args.fc >= 1.0):
        raise SceneError(f"--fc: the confidence factor must be >= 1, got {args.fc}")
    demand = None
    if args.sld_ag is not None and args.ag is None:
        raise SceneError("--sld-ag: give --ag too (the demand it belongs to); a scene's own demand takes its "
                         "damage limit state from demand.SLD")
    if args.ag is not None:
        given = dict(ag_g=args.ag, S=args.S, F0=args.F0, TB=args.TB, TC=args.TC, TD=args.TD, q=args.q, Z=args.Z,
                     H=args.H, N=args.N, T1=args.T1, xi1=args.xi1, xi_mech=args.xi_mech, Tc_star=args.Tc_star,
                     soil=args.soil, topography=args.topography, topography_ratio=args.topography_ratio)
        if args.sld_ag is not None:
            given["SLD"] = {k: v for k, v in dict(ag_g=args.sld_ag, F0=args.sld_F0, Tc_star=args.sld_Tc_star).items()
                            if v is not None}
        try:
            demand = from_mapping({k: v for k, v in given.items() if v is not None})
        except ValueError as exc:
            raise SceneError(str(exc).replace("demand.SLD.ag_g", "--sld-ag").replace("demand.SLD.F0", "--sld-F0")
                             .replace("demand.SLD.Tc_star", "--sld-Tc-star")
                             .replace("demand.ag_g", "--ag").replace("demand.xi_mech", "--xi-mech")
                             .replace("demand.Tc_star", "--Tc-star").replace("demand.topography_ratio",
                                                                             "--topography-ratio")
                             .replace("demand.", "--")) from None
    scene = load_scene(args.scene, strict=args.strict)
    from limit.model.assemble import Options

    opts = Options(settings=settings_of_args(args))  # a bad --set is rejected input (exit 2)
    try:
        own_demand = demand is None and args.fc is None  # the scene's demand: its check is made by analyse
        res = analyse(scene, method=args.method, options=opts, verdict=own_demand).data
        own = res.get("verdict") or {}
        if own_demand and own.get("status") == CheckStatus.DONE:
            a = {k: v for k, v in own.items() if k != "status"}
        else:
            import functools

            from limit.incremental_curve import follow_frictional

            a = verdict(scene, res, demand, args.fc, sliding=functools.partial(follow_frictional, options=opts))
    except ValueError as exc:
        print(f"failed: {exc}", file=sys.stderr)
        return 1
    print(format_assessment(a))
    if args.json:
        jsonio.write_json(args.json, a)
    return 0


def cmd_design(args) -> int:
    import json

    from limit import jsonio
    from limit.model.scene import load_scene
    from limit.solve.status import ANSWERED
    from limit.tie_design import design

    load_scene(args.scene)  # validated (exit 2 on bad input)
    with open(args.scene) as fh:
        data = json.load(fh)  # in its own units, as the candidates
    keep = []
    if args.levels is not None and not args.wall_to_wall:
        raise SceneError("--levels: goes with --wall-to-wall TAG_A TAG_B")
    if args.wall_to_wall:
        from limit.tie_candidates import wall_to_wall

        cands = wall_to_wall(data, *args.wall_to_wall, levels=args.levels)
        keep = list(data.get("ties", []))
        print(f"{len(cands)} candidate ties, wall to wall", file=sys.stderr)
    elif args.candidates:
        try:
            with open(args.candidates) as fh:
                cands = json.load(fh)
        except (OSError, ValueError) as exc:
            raise SceneError(f"--candidates: cannot read {args.candidates}: {exc}") from None
        if not isinstance(cands, list) or not all(isinstance(c, dict) for c in cands):
            raise SceneError('--candidates: a JSON list of tie objects ({"from": ..., "to": ...})')
        keep = list(data.get("ties", []))
    else:
        cands = list(data.get("ties", []))
    tell = lambda t: print(f"  {t}", file=sys.stderr, flush=True)  # noqa: E731
    changes = settings_of_args(args)  # a bad --set is rejected input (exit 2)
    try:
        if args.target_alpha is None:
            from limit.tie_design import design_for_demand

            out = design_for_demand(data, cands, method=args.method, keep=keep, progress=tell, settings=changes)
        else:
            out = design(data, cands, args.target_alpha, method=args.method, keep=keep, progress=tell,
                         settings=changes)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    lp = out["lp_capacities"]
    if lp is not None:
        print("least total capacity by the LP: " + ", ".join(
            f"{c.get('id', f'tie-{k}')} {v:.6g} N" for k, (c, v) in enumerate(zip(cands, lp))))
    if out["status"] != CheckStatus.DONE:
        print(f"design {out['status']}: {out['reason']}")
        return 1
    res = out["result"]
    nlp = res.get("nlp") or {}
    alpha = nlp.get("alpha") if nlp.get("status") in ANSWERED else res["lp"].get("alpha")
    print(f"designed ties (step 2's check: capacities x {out['factor']:.4g} of the LP's): " + (", ".join(
        f"{t.get('id', '?')} {t['capacity']:.6g} N" for t in out["ties"]) or "none needed"))
    print(f"alpha: LP {res['lp'].get('alpha')}, frictional {alpha} (target {out['target']:.6g}); "
          f"{out['time_s']:.1f} s")
    from limit.results.summary import format_result

    print("\n".join(format_result(res).splitlines()[1:]))  # the designed scene's mechanism and ties
    if args.dem:
        out["dem"] = _design_dem(dict(data, ties=keep + out["ties"]), out["target"])
    if out.get("check"):
        from limit.verdict.local_check import verdict_lines

        print("\n".join(verdict_lines(res["verdict"])))
    if args.output:
        jsonio.write_json(args.output, dict(data, ties=keep + out["ties"]))
        print(f"wrote {args.output}")
    if args.json:
        jsonio.write_json(args.json, {**{k: v for k, v in out.items() if k != "result"}, "result": res})
    return 0


def _design_dem(designed: dict, target: float) -> dict:
    """YADE's pushover of the designed scene (vertex model), printed against the target."""
    from dem_validation.api import run_scene

    print("YADE pushover of the designed scene ...", file=sys.stderr, flush=True)
    dem = run_scene(designed)
    a = dem.get("alpha")
    print(f"YADE: {dem['status']}" + (f", collapses at alpha = {a:.6g} ({100 * (a / target - 1):+.2f} % from the "
                                     f"target {target:.6g})" if a is not None else f" ({dem.get('reason', '')})"))
    return {k: dem.get(k) for k in ("status", "alpha", "reason", "time_s")}


def cmd_sweep(args) -> int:
    from limit import jsonio
    from limit.direction_sweep import format_direction, sweep

    if not (0 < args.step <= 180):
        raise SceneError(f"--step: must be in (0, 180] degrees, got {args.step}")
    from limit.model.scene import load_scene

    data = load_scene(args.scene).data  # validated (exit 2 on bad input)
    if data.get("dim") != 3:
        raise SceneError("dim: the direction sweep is for 3D scenes")
    changes = settings_of_args(args)  # a bad --set is rejected input (exit 2)
    try:
        out = sweep(data, args.step, mirror=True if args.mirror else None, jobs=args.jobs, scheduler=args.scheduler,
                    progress=lambda k, n: print(f"\r{k}/{n} directions", end="", file=sys.stderr, flush=True),
                    every=args.frictional, settings=changes)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    print(file=sys.stderr)
    nlp = (out.get("min_nlp") or {}).get("nlp") or {}
    d = out.get("min_direction")
    where = "" if d is None else f", live direction {format_direction(d, 4)}"
    print(f"minimum LP alpha {out['min_alpha']:.6g} at {out['min_theta']:g} deg (0 = the scene's live direction{where}); "
          f"frictional there: {nlp.get('alpha')} ({nlp.get('status')}); {out['time_s']:.1f} s")
    if args.frictional:
        if out.get("min_theta_frictional") is None:
            print("frictional: no direction has a verified step 2 point")
        else:
            print(f"minimum frictional alpha {out['min_alpha_frictional']:.6g} at {out['min_theta_frictional']:g} deg"
                  + ("" if out.get("min_direction_frictional") is None else
                     f", live direction {format_direction(out['min_direction_frictional'], 4)}")
                  + (" (not the LP's worst direction)" if _worse_elsewhere(out) else ""))
    if args.json:  # reports.plots.direction_polar draws it
        jsonio.write_json(args.json, out)
    if args.plot:
        from reports.plots import direction_polar

        direction_polar(out, args.plot, data.get("name", ""))
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _worse_elsewhere(out: dict, rtol: float = 1e-6) -> bool:
    """Whether the frictional minimum of a sweep lies below step 2's alpha in the LP's worst direction."""
    k = out["theta"].index(out["min_theta"]) if out.get("min_theta") is not None else None
    there = out["alpha_frictional"][k] if k is not None else float("nan")
    return not there <= out["min_alpha_frictional"] * (1.0 + rtol)


def cmd_solve(args) -> int:
    from limit import jsonio
    from limit.analysis import analyse
    from limit.model.assemble import Options
    from limit.model.scene import load_scene
    from limit.solve.status import Status
    from limit.results.summary import format_result

    if args.slide_faces is not None and (args.slide_faces < 4 or args.slide_faces % 2 or args.slide_faces > 360):
        raise SceneError(f"--slide-faces: must be an even number from 4 to 360, got {args.slide_faces}")
    changes = settings_of_args(args)
    scene = load_scene(args.scene, strict=args.strict)
    opts = Options(model=args.model, n_slide=args.slide_faces, slide_fit=args.slide_fit, settings=changes)
    nlp_options = {"solver": args.nlp_solver, "global_check": args.global_check, "iterative": args.iterative_lp,
                   "arbitrary": args.arbitrary_start}
    if args.nlp_time_budget is not None:
        if not args.nlp_time_budget > 0:
            raise SceneError(f"--nlp-time-budget: must be > 0 s, got {args.nlp_time_budget}")
        nlp_options["time_budget"] = args.nlp_time_budget
    if args.global_time_limit is not None:
        if not args.global_time_limit > 0:
            raise SceneError(f"--global-time-limit: must be > 0 s, got {args.global_time_limit}")
        nlp_options["global_time_limit"] = args.global_time_limit
    if args.dem_start is not None:
        from limit.solve.dem_start import state_of

        if args.method == "lp":
            raise SceneError("--dem-start: starts step 2, which --method lp does not run")
        try:
            import json

            with open(args.dem_start, encoding="utf-8") as fh:
                nlp_options["dem_state"] = state_of(json.load(fh))
        except (OSError, ValueError) as exc:
            raise SceneError(f"--dem-start {args.dem_start}: {exc}") from None
        unknown = sorted(set(nlp_options["dem_state"]["displacement"]) - {b.id for b in scene.blocks})
        if unknown:
            raise SceneError(f"--dem-start {args.dem_start}: block '{unknown[0]}' is not in the scene "
                             f"({len(unknown)} unknown id(s)): a DEM run of another scene?")
    cache, k = _solve_cache(args, scene, nlp_options, opts.settings)
    out = cache.get("solve", scene.name, k) if cache is not None else None
    if out is not None:
        print(format_result(out))
        print(f"(from the result cache, {cache.path('solve', scene.name, k)}; --no-cache solves again)",
              file=sys.stderr)
    else:
        out = analyse(scene, method=args.method, options=opts, solver=args.solver, fallback=not args.no_fallback,
                      check_kinematic=args.check_kinematic, nlp_options=nlp_options).data
        print(format_result(out))
        if cache is not None and Status.FAILED not in (out["lp"].get("status"), (out.get("nlp") or {}).get("status")):
            cache.put("solve", scene.name, k, out)  # a failed answer is solved again next time
    if args.json:
        jsonio.write_json(args.json, out)
    if args.plot:
        from limit.results.mechanism_plot import plot_mechanism

        written = plot_mechanism(scene, out, args.plot)
        if not written:
            print(f"no mechanism to draw: {args.plot} not written", file=sys.stderr)
        for path in written:
            print(f"wrote {path}", file=sys.stderr)
    failed = Status.FAILED in (out["lp"]["status"], (out.get("nlp") or {}).get("status"))
    return 1 if failed else 0


def settings_of_args(args) -> dict:
    """The settings that ``--set NAME=VALUE`` changes, {name: value} (the last one of a name
    wins); SceneError (exit 2) names a bad item's key."""
    from limit.settings import DEFAULT, parse

    changes = {}
    try:
        for item in args.set:
            key, value = parse(item)
            changes[key] = value
        DEFAULT.replace(changes)  # the ranges checked here, so that a bad value is rejected input
    except ValueError as exc:
        raise SceneError(f"--set: {exc}" if not str(exc).startswith("--set") else str(exc)) from None
    return changes


#: options of ``limit solve`` that decide nothing in its result (outputs and the cache itself), and
#: ``set``, which enters the key as the settings that differ from the defaults
NOT_IN_SOLVE_KEY = ("command", "scene", "json", "plot", "no_cache", "cache", "dem_start", "strict", "set")


def _solve_cache(args, scene, nlp_options, settings=None) -> tuple:
    """(cache, key) of a ``limit solve`` run, or (None, None) with ``--no-cache`` or LIMIT_NO_CACHE:
    the result file is kept by scene content, options (the DEM start's state included), the
    settings that differ from the defaults (:meth:`limit.settings.Settings.changed`) and the
    code's fingerprint (:mod:`reports.cache`), like ``make validate``'s stages."""
    if args.no_cache or os.environ.get("LIMIT_NO_CACHE"):
        return None, None
    from reports.cache import DEFAULT_DIR, Cache, key

    options = {k: v for k, v in vars(args).items() if k not in NOT_IN_SOLVE_KEY}
    options["dem_state"] = nlp_options.get("dem_state")
    changed = settings.changed() if settings is not None else {}
    if changed:
        options["settings"] = changed
    return Cache(args.cache or DEFAULT_DIR), key("solve", scene.data, options)


def cmd_info(args) -> int:
    from limit import jsonio
    from limit.results.info import format_info, scene_info
    from limit.model.scene import load_scene

    scene = load_scene(args.scene, strict=args.strict)
    info = scene_info(scene)
    print(format_info(info))
    if args.json:
        jsonio.write_json(args.json, info)
    return 0


def cmd_settings(args) -> int:
    from limit.settings import format_table

    print(format_table())
    return 0


def cmd_report(args) -> int:
    from reports.scene_report import run

    return run(args)


COMMANDS = {"info": cmd_info, "solve": cmd_solve, "check": cmd_check, "sweep": cmd_sweep, "design": cmd_design, "import": cmd_import,
            "build": cmd_build, "report": cmd_report, "settings": cmd_settings}


def _one_line_warnings() -> None:
    """Warnings as 'warning: message' lines on stderr (no source line)."""
    import warnings

    warnings.showwarning = lambda msg, cat, *a, **k: print(f"warning: {msg}", file=sys.stderr)


class _Stderr(logging.StreamHandler):
    """A handler that writes to the sys.stderr of the moment (callers and tests swap it)."""

    stream = property(lambda self: sys.stderr, lambda self, value: None)


def _progress_log() -> None:
    """Progress of long solves (the ``limit`` loggers' INFO records) as lines on stderr where it
    is a terminal; the environment variable LIMIT_LOG_LEVEL (INFO, WARNING, ...) sets the level
    anywhere. Python callers configure the ``limit`` logger as usual."""
    level = os.environ.get("LIMIT_LOG_LEVEL") or ("INFO" if sys.stderr.isatty() else "WARNING")
    logger = logging.getLogger("limit")
    if not any(isinstance(h, _Stderr) for h in logger.handlers):
        handler = _Stderr()
        handler.setFormatter(logging.Formatter("%(message)s"))
        logger.addHandler(handler)
    try:
        logger.setLevel(level.upper())
    except ValueError:
        raise SceneError(f"LIMIT_LOG_LEVEL: {level!r} is not a logging level (DEBUG, INFO, WARNING, ERROR)") from None


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    _one_line_warnings()

    def command() -> int:
        _progress_log()  # inside run_command: a bad LIMIT_LOG_LEVEL is a rejection (exit 2)
        return COMMANDS[args.command](args)

    return run_command(command, debug_env="LIMIT_DEBUG")
