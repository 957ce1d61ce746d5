"""VTK export of the blocks and their mechanisms, for ParaView.

Legacy VTK POLYDATA (ASCII): every block face is a polygon (2D blocks as one
polygon in z = 0; a compound block as its convex parts), each block keeps its own
copy of its vertices. Cell data: ``block`` (index), ``fixed`` (0/1) and the field
``block_id`` (the scene's ids, one string per cell, spaces as %20). Point data: one
vector field per motion, the velocity of each vertex under that rigid-block motion:
``lp_mechanism``, ``nlp_mechanism`` (normalised to unit live-load work) and each
engine's displacement at collapse under its own name, ``yade_displacement`` and
``lmgc90_displacement`` (m); and the loads on each block, ``dead_load`` and
``live_load`` (the block's force resultant, N, at each of its vertices). In ParaView:
Warp By Vector on one of the motions.

Beside it, ``<OUT>-joints.vtk`` holds the joints (3D: polygons, 2D: segments) with their
state in each mechanism as cell data (``lp_state``, ``nlp_state``: 0 closed, 1 hinges or
opens, 2 slides, 3 twists; the later wins) and the joint's blocks in the field ``joint``.

``python -m reports.vtk SCENE.json [RESULT.json ...] -o OUT.vtk`` (results from
``limit solve --json`` and ``dem_validation run --json``, one engine's per file; each
engine keeps its own field).
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


#: the DEM parts of a result and the engine each means when the part does not name one
DEM_PARTS = {"dem": "yade", "lmgc": "lmgc90"}
#: joint states of the joints file, in the order a later one wins
JOINT_STATES = {"rock": 1, "open": 1, "slide": 2, "twist": 3}


def motions_of(result: dict) -> dict:
    """{field name: per-block motion dict} available in a result dict: the LP's and step 2's
    mechanisms, and each DEM part's displacement under its engine's name."""
    out = {}
    for part, name in (("lp", "lp_mechanism"), ("nlp", "nlp_mechanism")):
        m = (result.get(part) or {}).get("mechanism")
        if m:
            out[name] = m
    for part, default in DEM_PARTS.items():
        res = result.get(part) or {}
        if res.get("displacement"):
            out[f"{res.get('engine') or default}_displacement"] = res["displacement"]
    return out


def _string_field(name: str, values) -> list[str]:
    return ["FIELD FieldData 1", f"{name} 1 {len(values)} string"] + [str(v).replace("%", "%25").replace(" ", "%20")
                                                                        for v in values]


def _loads_per_block(scene) -> dict:
    """{"dead_load": (n_blocks, 3), "live_load": ...}: each free block's force resultant (N)."""
    from limit.model.loads import dead_and_live

    out = {}
    for name, f in zip(("dead_load", "live_load"), dead_and_live(scene)):
        F = np.zeros((len(scene.blocks), 3))
        for row, i in enumerate(scene.free):
            F[i, : scene.dim] = np.asarray(f)[row, : scene.dim]
        out[name] = F
    return out


def write_vtk(scene, motions: dict, path) -> Path:
    dim = scene.dim
    pts, polys, cell_block, cell_fixed = [], [], [], []
    fields = {name: [] for name in motions}
    loads = _loads_per_block(scene)
    load_fields = {name: [] for name in loads}
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
        for name, F in loads.items():
            load_fields[name].append(np.tile(F[b.index], (len(V), 1)))
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
    lines += _string_field("block_id", [scene.blocks[c].id for c in cell_block])
    lines.append(f"POINT_DATA {len(P)}")
    for name, parts in {**fields, **load_fields}.items():
        lines.append(f"VECTORS {name} double")
        lines += [" ".join(f"{x:.10g}" for x in v) for v in np.vstack(parts)]
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text("\n".join(lines) + "\n")
    return p


def write_joints_vtk(scene, result: dict, path, interfaces=None) -> Path:
    """The joints file (see the module's docstring) of ``scene`` with the states of the result's
    ``lp`` and ``nlp`` parts (their ``interfaces``: indices of the joints that rock, open, slide,
    twist; a part without them gives 0 everywhere)."""
    from limit.geom.interfaces import find_interfaces

    I = find_interfaces(scene) if interfaces is None else interfaces
    polys = [np.asarray(I.polygons[j], dtype=float) for j in range(len(I))]
    pts, cells, offset = [], [], 0
    for V in polys:
        V3 = np.column_stack([V, np.zeros(len(V))]) if scene.dim == 2 else V
        pts.append(V3)
        cells.append(list(range(offset, offset + len(V3))))
        offset += len(V3)
    P = np.vstack(pts) if pts else np.zeros((0, 3))
    kind = "LINES" if scene.dim == 2 else "POLYGONS"
    lines = ["# vtk DataFile Version 3.0", f"{scene.name}: joints and their states", "ASCII", "DATASET POLYDATA",
             f"POINTS {len(P)} double"] + [" ".join(f"{x:.10g}" for x in p) for p in P]
    lines.append(f"{kind} {len(cells)} {sum(len(c) + 1 for c in cells)}")
    lines += [" ".join(map(str, [len(c)] + c)) for c in cells]
    lines.append(f"CELL_DATA {len(cells)}")
    for part in ("lp", "nlp"):
        state = np.zeros(len(cells), dtype=int)
        faces = (result.get(part) or {}).get("interfaces") or {}
        for key, code in JOINT_STATES.items():
            for j in faces.get(key, []):
                if j < len(state):
                    state[j] = max(state[j], code)
        lines += [f"SCALARS {part}_state int 1", "LOOKUP_TABLE default"] + [str(v) for v in state]
    lines += _string_field("joint", [f"{a}|{b}" for a, b in I.pairs(scene)])
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text("\n".join(lines) + "\n")
    return p


def joints_path(path) -> Path:
    p = Path(path)
    return p.with_name(f"{p.stem}-joints{p.suffix or '.vtk'}")


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
    merged, motions = {}, {}
    for r in args.results:
        try:
            data = json.loads(Path(r).read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise SceneError(f"{r}: not a readable result file ({exc})") from None
        motions.update(motions_of(data))  # each engine's under its own name: none is lost
        merged.update({k: v for k, v in data.items() if k in ("lp", "nlp")})
    p = write_vtk(scene, motions, args.out)
    q = write_joints_vtk(scene, merged, joints_path(args.out))
    print(f"wrote {p} and {q}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
