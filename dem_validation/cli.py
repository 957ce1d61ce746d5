"""Command line: ``python -m dem_validation run SCENE.json [--json OUT.json] [knobs]``.

Prints a short summary; ``--json`` writes ``{"scene", "n_blocks",
"n_free_blocks", "n_interfaces", "dem": {...}}`` (docs/formats.md, 'Result file').
Exit status: 0 when the DEM ran (collapsed or stable), 2 for a rejected
scene or option (one line on stderr), 1 for a failed DEM run (the result file
is still written, with ``"status": "failed"`` and the reason) or any other
failure.
"""
from __future__ import annotations

import argparse
import math
import sys
import time

from . import engines
from . import params as P


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m dem_validation", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="quasi-static pushover of a scene in YADE (default) or LMGC90")
    r.add_argument("scene")
    r.add_argument("--json", metavar="OUT.json", help="write the result file")
    r.add_argument("--eps", metavar="E1,E2", help="settlement strains, e.g. 1e-5,2.5e-6 (default %s)" % "; ".join(
        f"{c}: " + ",".join(f"{e:g}" for e in d["eps"]) for c, d in P.BY_CONTACT.items()))
    r.add_argument("--contact", choices=("vertex", "polyhedra"), default="vertex",
                   help="block model: vertex spheres against faces (default) or YADE Polyhedra (slower)")
    r.add_argument("--engine", choices=engines.names(), default=engines.DEFAULT, help=engines.help_text())
    r.add_argument("--timeout", type=float, default=1800.0, metavar="S", help="wall-clock limit in s (default 1800)")
    r.add_argument("--yade", metavar="PATH", help="YADE executable (default $DEM_YADE or yade on PATH)")
    r.add_argument("--set", action="append", default=[], metavar="KNOB=VALUE",
                   help="any other knob (repeatable): " + ", ".join(k for k in P.KNOBS if k != "eps"))
    r.add_argument("--quiet", action="store_true", help="no progress lines")
    r.add_argument("--no-bracket", action="store_true",
                   help="do not check the collapse alpha against the limit analysis (by default a result below "
                        "step 2's frictional alpha or above the LP's is marked suspect: dem.bracket)")
    return p


def _knobs(args) -> dict:
    knobs = {}
    if args.eps:
        knobs["eps"] = [float(x) for x in args.eps.split(",") if x.strip()]
    for item in args.set:
        key, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--set {item!r}: expected KNOB=VALUE")
        knobs[key.strip()] = float(value)
    return knobs


#: the terminal shows a YADE step line at most every this many seconds (the engine sends one
#: every 1000 steps: by step count, so that its runs do not depend on the clock)
SHOW_EVERY_S = 2.0


class _Progress:
    """Prints progress records on stderr; YADE's step lines at most every ``every`` s."""

    def __init__(self, every=SHOW_EVERY_S):
        self.every, self.shown = every, -math.inf

    def __call__(self, info):
        if "step" in info and "outcome" not in info:
            now = time.monotonic()
            if now - self.shown < self.every:
                return
            self.shown = now
        _progress(info)


def _progress(info):
    if "outcome" in info:  # LMGC90: one line per trial
        print(f"lmgc90: {'dt=%.3g s ' % info['dt'] if 'dt' in info else ''}{info['phase']} alpha={info['alpha']:.5g} "
              f"{info['outcome']} step={info['step']}",
              file=sys.stderr, flush=True)
    elif "step" in info:
        print(f"dem: eps={info.get('eps', 0):.0e} alpha={info['alpha']:.5g} step={info['step']} "
              f"residual={info['residual']:.2e} motion={info.get('motion', 0):.2e} m", file=sys.stderr, flush=True)
    elif info.get("phase") == "stiffness":
        print(f"dem: contacts eps={info['eps']:.0e}, dt={info['dt']:.3g} s", file=sys.stderr, flush=True)


def summary(result: dict) -> str:
    dem = result["dem"]
    lines = [f"{result['scene']}: {result['n_blocks']} blocks ({result['n_free_blocks']} free), "
             f"{result['n_interfaces']} interfaces"]
    if dem["status"] == "collapsed" and dem.get("alpha") is not None:
        lines.append(engines.of_result(dem).collapse_line(dem))
        if len(dem.get("runs") or []) > 1 and all("dt" in r for r in dem["runs"]):
            lines.append("time steps: " + ", ".join(f"{r['dt']:.3g} s: {r['alpha']:.5g}" for r in dem["runs"]
                                                    if r.get("alpha") is not None)
                         + {True: " (converged)", False: " (not converged)"}.get(dem.get("dt_converged"), ""))
    elif dem["status"] == "failed":
        lines.append(f"DEM failed: {dem.get('reason')}")
    else:
        lines.append(f"DEM {dem['status']}: {dem.get('note', '')}".rstrip())
    br = dem.get("bracket")
    if br and br.get("verdict") == "suspect":
        lines.append(f"SUSPECT ({br['side']}): {br['reason']}")
    elif br and br.get("verdict") == "inside":
        lines.append(f"inside the limit-analysis bracket: {br['reason']}")
    lines.append(f"time {dem.get('time_s', 0):.1f} s, {dem.get('steps', 0)} steps")
    return "\n".join(lines)


def cmd_run(args) -> int:
    from limit import jsonio
    from limit.geom.interfaces import find_interfaces
    from limit.model.pair_checks import check_friction_pairs
    from limit.model.scene import load_scene

    eng = engines.get(args.engine)
    try:
        p = eng.knobs(_knobs(args), args.contact)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    scene = load_scene(args.scene)
    I = find_interfaces(scene)
    check_friction_pairs(scene, I)  # an override that applies to no joint: exit 2, as in limit solve
    progress = None if args.quiet else _Progress()
    dem = eng.run(scene, p, timeout_s=args.timeout, progress=progress, executable=args.yade, interfaces=I,
                  contact=args.contact).to_dict()
    result = {"scene": scene.name, "n_blocks": scene.n_blocks, "n_free_blocks": int(len(scene.free)),
              "n_interfaces": len(I), "dem": dem}
    if args.json:  # first: neither the bracket's limit analysis nor the summary may lose the run
        jsonio.write_json(args.json, result)
    if not args.no_bracket and dem.get("status") == "collapsed" and dem.get("alpha") is not None:
        from .bracket import judge_with_start, limit_analysis

        if not args.quiet:
            print("checking the collapse against the limit analysis (LP and step 2; --no-bracket skips it) ...",
                  file=sys.stderr)
        try:
            dem["bracket"] = judge_with_start(scene, dem, limit_analysis(scene))
        except Exception as exc:  # noqa: BLE001 - the DEM result is kept whatever the check does
            dem["bracket"] = {"verdict": "unchecked", "reason": f"the limit analysis failed: {type(exc).__name__}: {exc}"}
        dem["suspect"] = dem["bracket"]["verdict"] == "suspect"
        if args.json:
            jsonio.write_json(args.json, result)
    print(summary(result))
    return 1 if dem["status"] == "failed" else 0


def main(argv=None) -> int:
    from limit.errors import run_command

    args = _parser().parse_args(argv)
    return run_command(lambda: cmd_run(args), debug_env="DEM_DEBUG")
