"""``limit build KIND [--option VALUE ...] -o SCENE.json``: the command line of :mod:`scenes.generators`.

One subcommand per generator (``arch``, ``wall``, ``corner``, ``tee``, ``buttress``,
``barrel-vault``, ``cross-vault``, ``dome``); its options are the generator's parameters
(``--pier-height 1.5``, ``--unit 0.4 0.2 0.2``, ``--opening X WIDTH SILL HEIGHT [HEAD]``, ``--stagger``
/ ``--no-stagger``), lengths in metres. The scene is checked (limit.model.scene.load_scene) and
written; a bad value exits with status 2 and one line naming the option.
"""
from __future__ import annotations

import argparse
import inspect
import json
import re

from limit.errors import SceneError

#: parameters whose default is None, and the type their value takes
_NONE_TYPES = {"buttress_courses": int, "n": int}
#: parameters given as several numbers
_LISTS = {"unit": 3, "buttresses": "+"}


def _param_help(fn) -> dict:
    """name -> description, from the generator's docstring lines ``name: text`` (continued on
    lines indented further)."""
    out, last = {}, None
    for line in (fn.__doc__ or "").splitlines():
        m = re.match(r"    ([a-z_]+): (.*)", line)
        if m:
            last = m.group(1)
            out.setdefault(last, m.group(2).strip())
        elif last and line.startswith("        "):
            out[last] += " " + line.strip()
        else:
            last = None
    return out


def _summary(fn) -> str:
    first = (fn.__doc__ or "").strip().splitlines()[0]
    return first.split("; returns")[0].rstrip(".") + "."


def add_arguments(p) -> None:
    from . import GENERATORS

    sub = p.add_subparsers(dest="kind", required=True, metavar="KIND")
    for kind, fn in GENERATORS.items():
        doc = _summary(fn)
        sp = sub.add_parser(kind, help=doc, description=doc)
        sp.add_argument("-o", "--output", required=True, metavar="SCENE.json", help="the scene file to write")
        helps = _param_help(fn)
        for name, par in inspect.signature(fn).parameters.items():
            if name == "openings":
                sp.add_argument("--opening", action="append", nargs="+", metavar="V",
                                dest="p_openings",
                                help="an opening, X WIDTH SILL HEIGHT [HEAD]: left edge, clear width, sill and clear "
                                     "height (m), head 'lintel' (default) or 'arch' (repeat for more)")
                continue
            opt = "--" + name.replace("_", "-")
            h = helps.get(name, "")
            dflt = par.default
            if isinstance(dflt, bool):
                sp.add_argument(opt, dest=f"p_{name}", action=argparse.BooleanOptionalAction, default=None,
                                help=f"{h} (default: {'yes' if dflt else 'no'})")
            elif name in _LISTS:
                sp.add_argument(opt, dest=f"p_{name}", nargs=_LISTS[name], default=None,
                                metavar=("L", "W", "H") if name == "unit" else "X",
                                help=f"{h} (default: {' '.join(f'{v:g}' for v in dflt)})")
            else:
                sp.add_argument(opt, dest=f"p_{name}", default=None, metavar=name.upper(),
                                help=h if dflt is None else f"{h} (default: {dflt})")


def _number(opt, text, kind):
    try:
        return kind(text)
    except ValueError:
        raise SceneError(f"{opt}: expected {'a whole number' if kind is int else 'a number'}, got {text!r}") from None


def _convert(fn, args) -> dict:
    kw = {}
    for name, par in inspect.signature(fn).parameters.items():
        val = getattr(args, f"p_{name}", None)
        if val is None:
            continue
        opt = "--" + name.replace("_", "-")
        dflt = par.default
        if name == "openings":
            ops = []
            for k, o in enumerate(val):
                if len(o) not in (4, 5):
                    raise SceneError(f"--opening: expected X WIDTH SILL HEIGHT [HEAD], got {' '.join(o)!r}")
                d = {key: _number("--opening", v, float) for key, v in zip(("x", "width", "sill", "height"), o)}
                if len(o) == 5:
                    d["head"] = o[4]
                ops.append(d)
            kw[name] = ops
        elif isinstance(dflt, bool) or name == "name":
            kw[name] = val
        elif name in _LISTS:
            kw[name] = tuple(_number(opt, v, float) for v in val)
        elif isinstance(dflt, int) or _NONE_TYPES.get(name) is int:
            kw[name] = _number(opt, val, int)
        elif isinstance(dflt, str):
            kw[name] = val
        else:
            kw[name] = _number(opt, val, float)
    return kw


def run(args) -> int:
    from limit.geom.interfaces import find_interfaces
    from limit.model.scene import load_scene

    from . import GENERATORS

    fn = GENERATORS[args.kind]
    scene = fn(**_convert(fn, args))
    sc = load_scene(scene)
    n_if = len(find_interfaces(sc))
    with open(args.output, "w") as fh:
        fh.write(json.dumps(scene, indent=1) + "\n")
    print(f"{args.output}: {scene['name']}, {sc.n_blocks} blocks ({sc.n_fixed} fixed), {n_if} interfaces, "
          f"mass {sc.total_mass:.6g} kg")
    return 0
