"""Command line: ``limit info|solve SCENE.json [--json OUT.json]`` (or ``python -m limit``).

Exit status (docs/formats.md, 'Commands'): 0 success, 2 rejected input (one line on
stderr, no traceback), 1 any other failure, 130 interrupted.
"""
from __future__ import annotations

import argparse
import sys

from .errors import SceneError, run_command

#: the names of limit.lp.SOLVERS (not imported here: cvxpy is slow to import for `info`)
LP_SOLVERS = ["auto", "ipm", "clarabel", "ecos", "highs", "highs-ipm"]


def _parser() -> argparse.ArgumentParser:
    from . import __version__

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
    ps.add_argument("--solver", choices=LP_SOLVERS, default="auto",
                    help="LP solver (default auto: the structured interior point method 'ipm' from 3,000 "
                         "block unknowns on, clarabel below); a failed check falls back to another")
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
                    help="also compute the global frictional minimum by mixed-integer LP (scenes up to 30 free blocks)")
    ps.add_argument("--iterative-lp", action="store_true",
                    help="also run the iterative LP of Gilbert, Casapulla & Ahmed (2006)")
    ps.add_argument("--arbitrary-start", action="store_true",
                    help="also run the NLP from an arbitrary start (the paper's Fig. 4 comparison)")
    ps.add_argument("--nlp-time-budget", type=float, default=None, metavar="S",
                    help="wall-clock budget of step 2 in s: no restart begins after it (default 120)")
    return p


def cmd_solve(args) -> int:
    from . import jsonio
    from .analysis import analyse, public
    from .assemble import Options
    from .scene import load_scene
    from .summary import format_result

    if args.slide_faces is not None and (args.slide_faces < 4 or args.slide_faces % 2 or args.slide_faces > 360):
        raise SceneError(f"--slide-faces: must be an even number from 4 to 360, got {args.slide_faces}")
    scene = load_scene(args.scene, strict=args.strict)
    opts = Options(model=args.model, n_slide=args.slide_faces, slide_fit=args.slide_fit)
    nlp_options = {"solver": args.nlp_solver, "global_check": args.global_check, "iterative": args.iterative_lp,
                   "arbitrary": args.arbitrary_start}
    if args.nlp_time_budget is not None:
        if not args.nlp_time_budget > 0:
            raise SceneError(f"--nlp-time-budget: must be > 0 s, got {args.nlp_time_budget}")
        nlp_options["time_budget"] = args.nlp_time_budget
    res = analyse(scene, method=args.method, options=opts, solver=args.solver,
                  fallback=not args.no_fallback, check_kinematic=args.check_kinematic, nlp_options=nlp_options)
    print(format_result(res))
    if args.json:
        jsonio.write_json(args.json, public(res))
    failed = res["lp"]["status"] == "failed" or res.get("nlp", {}).get("status") == "failed"
    return 1 if failed else 0


def cmd_info(args) -> int:
    from . import jsonio
    from .info import format_info, scene_info
    from .scene import load_scene

    scene = load_scene(args.scene, strict=args.strict)
    info = scene_info(scene)
    print(format_info(info))
    if args.json:
        jsonio.write_json(args.json, info)
    return 0


COMMANDS = {"info": cmd_info, "solve": cmd_solve}


def _one_line_warnings() -> None:
    """Warnings as 'warning: message' lines on stderr (no source line)."""
    import warnings

    warnings.showwarning = lambda msg, cat, *a, **k: print(f"warning: {msg}", file=sys.stderr)


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    _one_line_warnings()
    return run_command(lambda: COMMANDS[args.command](args), debug_env="LIMIT_DEBUG")
