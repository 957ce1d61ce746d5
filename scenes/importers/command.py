"""``limit import FILE... -o SCENE.json``: the command line of :mod:`scenes.importers`.

Reads the files (:mod:`scenes.importers.readers`), repairs and snaps the blocks
(:mod:`scenes.importers.pipeline`), writes a ``blockscene/1`` scene in metres with the
default loads (self weight dead, a body force along +x live), checks that the scene
loads, and prints the summary (:mod:`scenes.importers.summary`). trimesh and ezdxf are
imported only when the command runs.
"""
from __future__ import annotations

SCALE = {"m": 1.0, "cm": 0.01, "mm": 0.001}
#: $INSUNITS codes of a DXF header that name a length unit this command knows
DXF_UNITS = {4: "mm", 5: "cm", 6: "m"}


def add_arguments(p) -> None:
    p.add_argument("files", nargs="+", metavar="FILE", help="OBJ, STL, PLY or DXF files, or folders of them")
    p.add_argument("-o", "--output", required=True, metavar="SCENE.json")
    p.add_argument("--units", choices=list(SCALE), default=None,
                   help="length unit of the files (default: a DXF's $INSUNITS when mm, cm or m, else m)")
    p.add_argument("--fixed", nargs="+", default=[], metavar="ID", help="fix these blocks (ids as printed/written)")
    p.add_argument("--fixed-lowest", action="store_true",
                   help="fix the blocks whose lowest point lies at the model's lowest level, within the gap tolerance "
                        "(the default when no other support option is given)")
    p.add_argument("--fixed-below", type=float, default=None, metavar="Z",
                   help="fix the blocks whose lowest point lies below Z (height, in the files' units)")
    p.add_argument("--friction", type=float, default=0.6, metavar="MU", help="friction coefficient (default 0.6)")
    p.add_argument("--density", type=float, default=2000.0, help="density in kg/m^3 (default 2000)")
    p.add_argument("--thickness", type=float, default=None,
                   help="2D: out-of-plane thickness in the files' units (default 1 m)")
    p.add_argument("--gap", type=float, default=None,
                   help="joint gap/overlap tolerance in the files' units (default 0.15 x the median block width; "
                        "0 keeps every gap open)")
    p.add_argument("--flat", type=float, default=None,
                   help="flatness tolerance of free faces in the files' units (default 0.01 x the median block width)")
    p.add_argument("--angle", type=float, default=5.0, help="joint faces' angle tolerance in degrees (default 5)")
    p.add_argument("--volume-tol", type=float, default=0.01,
                   help="a block whose convex hull exceeds its volume by at most this fraction is one convex block "
                        "(default 0.01); any other becomes a compound block")
    p.add_argument("--tolerance", type=float, default=None,
                   help="the scene's contact tolerance in the files' units (default: 1e-6 of the model's diagonal, "
                        "or the planes' residual, at most 1e-3 of the median block width)")
    p.add_argument("--name", default=None, help="scene name (default: the output file's stem)")
    p.add_argument("--no-check", action="store_true", help="do not load the written scene to check it and count interfaces")


def _units(args, files) -> tuple[str, list]:
    notes = []
    if args.units:
        return args.units, notes
    found = set()
    for f in files:
        if f.suffix.lower() == ".dxf":
            from ezdxf import recover

            try:
                doc, _ = recover.readfile(str(f))
                code = int(doc.header.get("$INSUNITS", 0))
            except Exception:
                code = 0
            if code in DXF_UNITS:
                found.add(DXF_UNITS[code])
    if len(found) == 1:
        u = found.pop()
        notes.append(f"units {u} from the DXF header ($INSUNITS); --units overrides it")
        return u, notes
    return "m", notes


def run(args) -> int:
    import json
    import warnings
    from pathlib import Path

    import numpy as np

    from limit.errors import SceneError
    from scenes.importers import pipeline, readers, summary

    import time

    msgs = []
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        files = readers.expand_paths(args.files)
        units, notes = _units(args, files)
        dim, raw = readers.read_files(files)
        t_read = time.perf_counter() - t0
        opts = pipeline.Options(gap=args.gap, flat=args.flat, angle_deg=args.angle, vol_tol=args.volume_tol,
                                min_width=1.5 * args.tolerance if args.tolerance else 0.0)
        built = pipeline.build(dim, raw, opts)
    times = {"read_s": t_read, **built.times}
    msgs += [str(w.message) for w in caught if issubclass(w.category, UserWarning) and "ezdxf" not in str(w.filename)]
    msgs += built.warnings
    scale = SCALE[units]
    width_m = built.tol["median_width"] * scale
    if args.units is None and units == "m" and width_m > 5:
        msgs.append(f"the median block is {width_m:.3g} m wide in metres: if the files are in mm or cm, pass --units")
    ids = [b.id for b in built.blocks]
    up = dim - 1
    low = np.array([(b.vertices if b.parts is None else np.vstack(b.parts))[:, up].min() for b in built.blocks])
    fixed = set()
    for bid in args.fixed:
        if bid not in ids:
            raise SceneError(f"--fixed: no block '{bid}' (ids: {', '.join(ids[:8])}{', ...' if len(ids) > 8 else ''})")
        fixed.add(bid)
    if args.fixed_below is not None:
        fixed |= {i for i, z in zip(ids, low) if z < args.fixed_below}
    use_lowest = args.fixed_lowest or (not args.fixed and args.fixed_below is None)
    if use_lowest:
        if not (args.fixed_lowest):
            notes.append("no support option given: the blocks at the lowest level are fixed (--fixed-lowest)")
        fixed |= {i for i, z in zip(ids, low) if z <= low.min() + built.tol["gap"]}
    if not fixed:
        msgs.append("no block is fixed: the scene needs at least one support (--fixed, --fixed-below, --fixed-lowest)")
    if len(fixed) == len(ids):
        msgs.append("every block is fixed: nothing can move")

    thickness_m = args.thickness * scale if args.thickness is not None else 1.0
    blocks = []
    for b in built.blocks:
        bd = {"id": b.id}
        if b.parts is None:
            bd["vertices"] = (b.vertices * scale).tolist()
        else:
            bd["parts"] = [{"vertices": (p * scale).tolist()} for p in b.parts]
        if b.id in fixed:
            bd["fixed"] = True
        if b.tags:
            bd["tags"] = list(b.tags)
        blocks.append(bd)
    allv = np.vstack([(b.vertices if b.parts is None else np.vstack(b.parts)) for b in built.blocks]) * scale
    diag = float(np.linalg.norm(np.ptp(allv, axis=0)))
    # the loader's default (1e-6 of the diagonal), or the planes' residual where corners met more
    # planes than they could lie on, capped at 1e-3 of the median block width
    tolerance = max(1e-6 * diag, min(4 * built.residual * scale, 1e-3 * width_m))
    # joints whose faces kept different planes (curved courses): the scene takes them as joints
    # within 1.25 x their measured tilt and separation (the margin covers the corners' moves onto
    # the planes), never beyond the import's own angle and gap tolerances
    n_tilted, tilt_deg, tilt_sep = built.tilted
    interfaces = {}
    if n_tilted:
        interfaces["angle_tolerance"] = round(min(1.25 * tilt_deg, args.angle), 6)
        tolerance = max(tolerance, min(1.25 * tilt_sep, built.tol["gap"]) * scale)
    if args.tolerance is not None:
        tolerance = args.tolerance * scale
    vol = sum(b.volume for b in built.blocks) * scale ** dim * (thickness_m if dim == 2 else 1.0)
    mass = float(args.density * vol)
    out = Path(args.output)
    scene = {
        "format": "blockscene/1",
        "name": args.name or out.stem,
        "dim": dim,
        "units": "m",
        "friction": args.friction,
        "density": args.density,
        "tolerance": tolerance,
        **({"thickness": thickness_m} if dim == 2 else {}),
        **({"interfaces": interfaces} if interfaces else {}),
        "blocks": blocks,
        "loads": {"dead": [{"type": "self_weight"}],
                  "live": [{"type": "body_force", "direction": [1, 0, 0] if dim == 3 else [1, 0]}]},
        "meta": {"source": "limit import " + " ".join(str(f) for f in files)},
    }
    n_interfaces = None
    rec = summary.record(files, units, scale, built, mass, tolerance, n_interfaces, sorted(fixed), msgs + notes)
    scene["meta"]["import"] = rec
    rec["times_s"] = times
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(scene, indent=1))
    problem = None
    if not args.no_check and fixed:
        from limit.geom.interfaces import find_interfaces
        from limit.model.scene import load_scene

        try:
            t0 = time.perf_counter()
            pipeline.log.info("import: %s written; checking it: loading, then its interfaces", out)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                sc = load_scene(scene)
            times["check_load_s"], t0 = time.perf_counter() - t0, time.perf_counter()
            n_interfaces = len(find_interfaces(sc))
            times["check_interfaces_s"] = time.perf_counter() - t0
            rec["interfaces"] = n_interfaces
            rec["mass_kg"] = float(sc.total_mass)
            out.write_text(json.dumps(scene, indent=1))
        except SceneError as exc:
            problem = str(exc)
    import sys

    for n in notes:
        print(f"note: {n}", file=sys.stderr)
    for m in msgs:
        print(f"warning: {m}", file=sys.stderr)
    print(summary.text(rec, str(out)))
    if problem:
        raise SceneError(f"{out} was written but does not load: {problem}")
    return 0
