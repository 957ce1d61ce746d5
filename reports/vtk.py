"""VTK export of the blocks and their mechanisms, for ParaView.

Legacy VTK POLYDATA (ASCII): every block face is a polygon (2D blocks as one
polygon in z = 0; a compound block as its convex parts), each block keeps its own
copy of its vertices. Cell data:
``block`` (index), ``fixed`` (0/1). Point data: one vector field per motion in
the result file, the velocity of each vertex under that rigid-block motion:
``lp_mechanism``, ``nlp_mechanism`` (normalised to unit live-load work) and
``dem_displacement`` (m). In ParaView: Warp By Vector on one of them.

``python -m reports.vtk SCENE.json [RESULT.json ...] -o OUT.vtk`` (results from
``limit solve --json`` and ``dem_validation run --json`` are merged).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from limit.model.dims import rigid_velocity


def _vertex_motion(block, piece, m, dim):
    v = rigid_velocity(m, piece.vertices - block.centroid, dim)
    return np.column_stack([v, np.zeros(len(v))]) if dim == 2 else v


def motions_of(result: dict) -> dict:
    """{field name: per-block motion dict} available in a result dict."""
    out = {}
    for part, key, name in (("lp", "mechanism", "lp_mechanism"), ("nlp", "mechanism", "nlp_mechanism"),
                            ("dem", "displacement", "dem_displacement")):
        m = (result.get(part) or {}).get(key)
        if m:
            out[name] = m
    return out


def write_vtk(scene, motions: dict, path) -> Path:
    dim = scene.dim
    pts, polys, cell_block, cell_fixed = [], [], [], []
    fields = {name: [] for name in motions}
    offset = 0
    for b, piece in ((b, piece) for b in scene.blocks for piece in b.pieces):
        V = piece.vertices
        V3 = np.column_stack([V, np.zeros(len(V))]) if dim == 2 else V
        pts.append(V3)
        if dim == 2:
            faces = [list(range(len(V)))]
        else:
            faces = [[int(np.argmin(np.linalg.norm(V - p, axis=1))) for p in f] for f in piece.faces]
        for f in faces:
            polys.append([offset + i for i in f])
            cell_block.append(b.index)
            cell_fixed.append(int(b.fixed))
        for name, mech in motions.items():
            m = mech.get(b.id)
            fields[name].append(np.zeros((len(V), 3)) if m is None or b.fixed else _vertex_motion(b, piece, m, dim))
        offset += len(V)
    P = np.vstack(pts)
    lines = ["# vtk DataFile Version 3.0", f"{scene.name}: blocks and collapse motions", "ASCII",
             "DATASET POLYDATA", f"POINTS {len(P)} double"]
    lines += [" ".join(f"{x:.10g}" for x in p) for p in P]
    size = sum(len(p) + 1 for p in polys)
    lines.append(f"POLYGONS {len(polys)} {size}")
    lines += [" ".join(map(str, [len(p)] + p)) for p in polys]
    lines += [f"CELL_DATA {len(polys)}", "SCALARS block int 1", "LOOKUP_TABLE default"]
    lines += [str(c) for c in cell_block]
    lines += ["SCALARS fixed int 1", "LOOKUP_TABLE default"] + [str(c) for c in cell_fixed]
    if fields:
        lines.append(f"POINT_DATA {len(P)}")
        for name, parts in fields.items():
            lines.append(f"VECTORS {name} double")
            lines += [" ".join(f"{x:.10g}" for x in v) for v in np.vstack(parts)]
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text("\n".join(lines) + "\n")
    return p


def main(argv=None) -> int:
    from limit.errors import run_command

    ap = argparse.ArgumentParser(prog="python -m reports.vtk", description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("results", nargs="*", help="result files (limit solve / dem_validation run --json)")
    ap.add_argument("-o", "--out", required=True)
    args = ap.parse_args(argv)
    return run_command(lambda: _run(args), debug_env="LIMIT_DEBUG")


def _run(args) -> int:
    from limit.errors import SceneError
    from limit.model.scene import load_scene

    scene = load_scene(args.scene)
    merged = {}
    for r in args.results:
        try:
            merged.update(json.loads(Path(r).read_text()))
        except (OSError, json.JSONDecodeError) as exc:
            raise SceneError(f"{r}: not a readable result file ({exc})") from None
    p = write_vtk(scene, motions_of(merged), args.out)
    print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
