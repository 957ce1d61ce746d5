"""Command line: ``python -m limit info|solve SCENE.json [--json OUT.json]``.

Exit status (CONTRACT.md section 2): 0 success, 2 rejected input (one line on
stderr, no traceback), 1 any other failure.
"""
from __future__ import annotations

import argparse
import os
import sys

from .errors import SceneError


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m limit", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    pi = sub.add_parser("info", help="check a scene and print its counts, mass and bounding box")
    pi.add_argument("scene")
    pi.add_argument("--json", metavar="OUT.json", help="also write the summary as JSON")
    return p


def cmd_info(args) -> int:
    from . import jsonio
    from .info import format_info, scene_info
    from .scene import load_scene

    scene = load_scene(args.scene)
    info = scene_info(scene)
    print(format_info(info))
    if args.json:
        jsonio.write_json(args.json, info)
    return 0


COMMANDS = {"info": cmd_info}


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    try:
        return COMMANDS[args.command](args)
    except SceneError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # an internal failure: one line, traceback on request
        if os.environ.get("LIMIT_DEBUG"):
            raise
        print(f"failed: {type(exc).__name__}: {exc} (set LIMIT_DEBUG=1 for a traceback)", file=sys.stderr)
        return 1
