"""Readers: geometry files to raw blocks (vertices and polygon faces), one per object.

A :class:`RawBlock` is what a file says about one block, before any repair: its
vertices ``(n, d)`` in the file's units, its faces as lists of vertex indices
(3D: polygons; 2D: one closed outline), the source it came from and its tags.

* OBJ: one block per ``o`` object (or ``g`` group when the file has no objects).
  The polygon faces are kept as written (trimesh's OBJ loader triangulates them,
  and a warped quad's plane comes from its four corners), so this reader reads
  ``v``, ``f``, ``o`` and ``g`` lines itself; everything else is ignored.
* STL, PLY (and any other mesh format trimesh loads): one block per file when
  several files or a folder are given; one file alone is split into its
  connected parts, one block each.
* DXF (ezdxf): LWPOLYLINE / POLYLINE outlines of three or more points make a 2D
  scene, one block each (an outline not marked closed is closed from its last
  point to its first, with a warning); POLYFACE meshes and 3DFACEs make a 3D scene, grouped
  into blocks by shared corners. The entity's layer becomes the block's tag.
* compas JSON (:mod:`scenes.importers.compas_json`): one block per compas mesh in the file.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from limit.errors import SceneError

MESH_SUFFIXES = {".stl", ".ply", ".off", ".glb", ".gltf"}


@dataclass
class RawBlock:
    """One block as read: ``vertices`` (n, d) in file units, ``faces`` a list of
    vertex-index lists (3D polygons, or one outline in 2D), ``name`` unique in the
    import, ``source`` the file (and object) it came from, ``tags`` e.g. the layer."""

    name: str
    vertices: np.ndarray
    faces: list
    source: str
    tags: list = field(default_factory=list)


def expand_paths(paths) -> list[Path]:
    """The files to read: each argument, or the geometry files of a folder (sorted)."""
    out = []
    for p in map(Path, paths):
        if p.is_dir():
            found = sorted(q for q in p.iterdir() if q.suffix.lower() in MESH_SUFFIXES | {".obj", ".dxf", ".json"})
            if not found:
                raise SceneError(f"{p}: no OBJ, STL, PLY, DXF or compas JSON file in this folder")
            out.extend(found)
        elif p.is_file():
            out.append(p)
        else:
            raise SceneError(f"{p}: no such file")
    return out


def read_files(paths) -> tuple[int, list[RawBlock]]:
    """(dim, raw blocks) of all the files; dim is 3 unless every file is a 2D DXF."""
    files = expand_paths(paths)
    blocks, dims = [], set()
    one_mesh_file = len(files) == 1
    for f in files:
        suffix = f.suffix.lower()
        if suffix == ".obj":
            dim, got = 3, read_obj(f)
        elif suffix == ".dxf":
            dim, got = read_dxf(f)
        elif suffix == ".json":
            from .compas_json import read_compas_json

            dim, got = 3, read_compas_json(f)
        else:
            dim, got = 3, read_mesh(f, split=one_mesh_file)
        dims.add(dim)
        blocks.extend(got)
    if len(dims) > 1:
        raise SceneError(f"{', '.join(map(str, files))}: mixes 2D outlines and 3D solids in one import")
    if not blocks:
        raise SceneError(f"{', '.join(map(str, files))}: no block found")
    _unique_names(blocks)
    return dims.pop(), blocks


def _unique_names(blocks: list[RawBlock]) -> None:
    seen: dict[str, int] = {}
    for b in blocks:
        base = b.name
        n = seen.get(base, 0)
        if n:
            b.name = f"{base}_{n}"
            while b.name in seen:
                n += 1
                b.name = f"{base}_{n}"
        seen[base] = n + 1
        seen.setdefault(b.name, 1)


def read_obj(path: Path) -> list[RawBlock]:
    """Blocks of a Wavefront OBJ file: one per ``o`` object, or per ``g`` group when
    there is no ``o`` line, or the whole file. Face indices may be negative (relative)
    and carry ``/vt/vn`` parts, which are dropped."""
    verts: list = []
    groups: dict[str, list] = {}
    order: list[str] = []
    has_o = False
    current_o, current_g = None, None
    with open(path, "r", errors="replace") as fh:
        lines = fh.read().splitlines()
    has_o = any(ln.startswith("o ") for ln in lines)
    for lineno, line in enumerate(lines, 1):
        parts = line.split()
        if not parts or parts[0].startswith("#"):
            continue
        key = parts[0]
        if key == "v":
            try:
                verts.append([float(x) for x in parts[1:4]])
            except ValueError:
                raise SceneError(f"{path}:{lineno}: vertex with a non-numeric coordinate") from None
            if len(verts[-1]) != 3:
                raise SceneError(f"{path}:{lineno}: vertex needs three coordinates")
        elif key == "o":
            current_o = " ".join(parts[1:]) or f"object{len(order)}"
        elif key == "g":
            current_g = " ".join(parts[1:]) or None
        elif key == "f":
            name = (current_o if has_o else current_g) or path.stem
            try:
                idx = [int(p.split("/")[0]) for p in parts[1:]]
            except ValueError:
                raise SceneError(f"{path}:{lineno}: face with a non-integer vertex index") from None
            n = len(verts)
            idx = [i - 1 if i > 0 else n + i for i in idx]
            if any(i < 0 or i >= n for i in idx):
                raise SceneError(f"{path}:{lineno}: face refers to a vertex not defined before it (object '{name}')")
            if name not in groups:
                groups[name] = []
                order.append(name)
            groups[name].append(idx)
    V = np.array(verts, dtype=float).reshape(-1, 3)
    out = []
    for name in order:
        faces = groups[name]
        used = np.unique(np.concatenate([np.asarray(f) for f in faces]))
        remap = {int(u): k for k, u in enumerate(used)}
        out.append(RawBlock(_clean(name), V[used], [[remap[i] for i in f] for f in faces],
                            f"{path.name}:{name}"))
    return out


def _clean(name: str) -> str:
    return "_".join(str(name).split()) or "block"


def read_mesh(path: Path, split: bool) -> list[RawBlock]:
    """Blocks of a triangle-mesh file read by trimesh (STL, PLY, OFF, glTF): the whole
    file, or with ``split`` its connected parts (by shared vertices after merging)."""
    import trimesh

    try:
        loaded = trimesh.load(str(path), process=False, force="mesh")
    except Exception as exc:  # trimesh raises many kinds for a broken file
        raise SceneError(f"{path}: cannot read it as a mesh ({type(exc).__name__}: {exc})") from None
    if not len(loaded.faces):
        raise SceneError(f"{path}: has no faces")
    V = np.asarray(loaded.vertices, dtype=float)
    F = np.asarray(loaded.faces)
    if not split:
        return [RawBlock(_clean(path.stem), V, [list(map(int, f)) for f in F], path.name)]
    # the closed parts, as for DXF faces: blocks that touch share corners and joint edges
    out = _group_faces(path, [(V[f], "0", str(k)) for k, f in enumerate(F)], prefix=_clean(path.stem) + "_")
    if len(out) == 1:
        out[0].name, out[0].source = _clean(path.stem), path.name
    return out


def read_dxf(path: Path) -> tuple[int, list[RawBlock]]:
    """(dim, blocks) of a DXF file: closed polylines (2D) or polyface meshes and 3DFACEs (3D)."""
    import ezdxf
    from ezdxf import recover

    try:
        doc, auditor = recover.readfile(str(path))
    except (OSError, ezdxf.DXFStructureError) as exc:
        raise SceneError(f"{path}: cannot read it as DXF ({exc})") from None
    msp = doc.modelspace()
    outlines, faces3d = [], []
    open_count = 0
    ignored: dict[str, int] = {}
    for e in msp:
        kind = e.dxftype()
        if kind not in ("LWPOLYLINE", "POLYLINE", "3DFACE"):
            ignored[kind] = ignored.get(kind, 0) + 1
        layer = e.dxf.get("layer", "0")
        handle = e.dxf.get("handle", "?")
        if kind == "LWPOLYLINE":
            pts = [(p[0], p[1]) for p in e.get_points("xy")]
            if len(pts) > 2:
                outlines.append((pts, layer, handle, float(e.dxf.get("elevation", 0.0))))
                if not e.closed and not np.allclose(pts[0], pts[-1]):
                    open_count += 1
        elif kind == "POLYLINE":
            if e.is_poly_face_mesh or e.is_polygon_mesh:
                for face in e.faces() if e.is_poly_face_mesh else []:
                    faces3d.append(([tuple(v.dxf.location) for v in face], layer, handle))
            elif len(e.vertices) > 2:
                pts = [tuple(v.dxf.location) for v in e.vertices]
                outlines.append(([p[:2] for p in pts], layer, handle, float(pts[0][2]) if len(pts[0]) > 2 else 0.0))
                if not e.is_closed and not np.allclose(pts[0], pts[-1]):
                    open_count += 1
        elif kind == "3DFACE":
            pts = [tuple(e.dxf.get(f"vtx{i}")) for i in range(4)]
            if np.allclose(pts[2], pts[3]):
                pts = pts[:3]
            faces3d.append((pts, layer, handle))
    if ignored:
        import warnings
        warnings.warn(f"{path}: ignored " + ", ".join(f"{n} {k}" for k, n in sorted(ignored.items()))
                      + " (only polylines, polyface meshes and 3DFACEs are blocks)")
    if outlines and faces3d:
        raise SceneError(f"{path}: has both closed 2D outlines and 3D faces; import them from separate files")
    if outlines:
        blocks = []
        for k, (pts, layer, handle, _z) in enumerate(outlines):
            P = np.asarray(pts, dtype=float)
            if len(P) > 1 and np.allclose(P[0], P[-1]):
                P = P[:-1]
            blocks.append(RawBlock(f"{_clean(layer)}_{k}" if layer not in ("0", "") else f"block{k}", P,
                                   [list(range(len(P)))], f"{path.name}:{handle}", [] if layer == "0" else [layer]))
        if open_count:
            import warnings
            warnings.warn(f"{path}: {open_count} polyline(s) neither marked closed nor ending at their start, "
                          "closed from their last point to their first")
        return 2, blocks
    if faces3d:
        return 3, _group_faces(path, faces3d)
    raise SceneError(f"{path}: no closed polyline, polyface mesh or 3DFACE in its model space")


def _group_faces(path: Path, faces3d: list, prefix: str = "block") -> list[RawBlock]:
    """3D faces grouped into blocks. Corners closer than 1e-9 of the drawing's size are merged;
    the faces of one POLYFACE entity are one block; loose 3DFACEs are joined across edges that
    bound exactly two faces (an edge on a joint between two blocks bounds four), and a group left
    open (a joint face) closes the larger open group whose open edges include its own."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    pts = np.array([p for f, _, _ in faces3d for p in f], dtype=float)
    scale = float(np.ptp(pts, axis=0).max()) or 1.0
    key = np.round(pts / (1e-9 * scale)).astype(np.int64)
    _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inv = inv.ravel()
    faces, k = [], 0
    for f, _, _ in faces3d:
        g = [int(i) for i in inv[k:k + len(f)]]
        faces.append([v for j, v in enumerate(g) if v != g[j - 1]])
        k += len(f)
    n = len(faces)
    edges: dict = {}
    for i, f in enumerate(faces):
        for a, b in zip(f, f[1:] + f[:1]):
            edges.setdefault((min(a, b), max(a, b)), []).append(i)
    rows, cols = list(range(n)), list(range(n))
    # faces of one entity (a polyface mesh, or a 3DFACE on its own) belong together
    by_entity: dict = {}
    for i, (_, _, handle) in enumerate(faces3d):
        by_entity.setdefault(handle, []).append(i)
    for members in by_entity.values():
        rows += members[1:]
        cols += members[:-1]
    for fs in edges.values():
        if len(fs) == 2:
            rows.append(fs[0])
            cols.append(fs[1])
    m = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    _, label = connected_components(m, directed=False)

    def open_edges(members):
        count: dict = {}
        for i in members:
            f = faces[i]
            for a, b in zip(f, f[1:] + f[:1]):
                e = (min(a, b), max(a, b))
                count[e] = count.get(e, 0) + 1
        return {e for e, c in count.items() if c == 1}

    groups: dict = {}
    for i, c in enumerate(label):
        groups.setdefault(int(c), []).append(i)
    # an open group (a joint face, maybe in triangles) closes a larger open group whose open
    # edges include all of its own: two coincident joint faces close the blocks on either side
    opened = {g: open_edges(m) for g, m in groups.items()}
    for g in sorted((g for g in groups if opened[g]), key=lambda g: len(groups[g])):
        if not groups[g]:
            continue
        for h in sorted(groups, key=lambda h: -len(groups[h])):
            if h != g and len(groups[h]) > len(groups[g]) and opened[h] and opened[g] <= opened[h]:
                groups[h] += groups[g]
                groups[g] = []
                opened[h] = open_edges(groups[h])
                break
    out = []
    for c, idx in enumerate(m for m in groups.values() if m):
        used = np.unique([v for i in idx for v in faces[i]])
        remap = {int(u): j for j, u in enumerate(used)}
        V = pts[first[used]]
        layers = sorted({faces3d[i][1] for i in idx} - {"0", ""})
        out.append(RawBlock(f"{_clean(layers[0])}_{c}" if layers else f"{prefix}{c}", V,
                            [[remap[v] for v in faces[i]] for i in idx],
                            f"{path.name}:{faces3d[idx[0]][2]}", layers))
    return out
