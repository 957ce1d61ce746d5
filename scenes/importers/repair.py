"""Repair of one raw 3D block: merged vertices, unique faces, closedness, outward orientation, volume.

Conventions: ``vertices`` (n, 3) in file units; ``faces`` lists of vertex indices,
counter-clockwise seen from outside after :func:`repair` (right-handed about the
outward normal). The closed-mesh tests and the orientation fix are trimesh's, run on
the triangulation of the polygons (:func:`scenes.importers.planes.triangulate`); each polygon
follows its first triangle. The mesh volume of a warped polygon mesh is that of this
triangulation.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from limit.errors import SceneError


@dataclass
class Solid:
    """A repaired closed block: ``vertices`` (n, 3), outward polygon ``faces``, ``volume``
    (> 0, of the polygon mesh, file units^3), ``hull_volume`` (of its vertices' convex hull),
    ``notes`` what the repair changed (e.g. 'merged 4 duplicate vertices'), ``face_tris`` each
    face's triangles (t, 3) of vertex indices, outward, as used for the volume."""

    name: str
    source: str
    tags: list
    vertices: np.ndarray
    faces: list
    volume: float
    hull_volume: float
    notes: list
    face_tris: list | None = None

    @property
    def hull_ratio(self) -> float:
        """Convex hull volume / mesh volume (1 for a convex block, > 1 for a concave one)."""
        return self.hull_volume / self.volume


def merge_vertices(V: np.ndarray, faces: list, tol: float) -> tuple[np.ndarray, list, int]:
    """(vertices, faces, merged count): vertices closer than ``tol`` become one (their mean);
    repeated corners inside a face are dropped, faces left with fewer than 3 corners removed."""
    from scipy.cluster.hierarchy import fcluster, linkage

    if len(V) > 1 and tol > 0:
        label = fcluster(linkage(V, method="single"), t=tol, criterion="distance") - 1
    else:
        label = np.arange(len(V))
    n = int(label.max()) + 1
    W = np.zeros((n, V.shape[1]))
    np.add.at(W, label, V)
    W /= np.bincount(label, minlength=n)[:, None]
    out = []
    for f in faces:
        g = [int(label[i]) for i in f]
        g = [v for k, v in enumerate(g) if v != g[k - 1]] if len(g) > 1 else g
        if len(set(g)) >= 3:
            out.append(g)
    return W, out, len(V) - n


def unique_faces(faces: list) -> tuple[list, int]:
    """Faces with repeats removed (the same corners in any order or direction); the count removed."""
    seen, out = set(), []
    for f in faces:
        key = tuple(sorted(f))
        if key not in seen:
            seen.add(key)
            out.append(f)
    return out, len(faces) - len(out)


def repair(name: str, source: str, tags: list, V: np.ndarray, faces: list, tol: float) -> Solid:
    """Merge vertices within ``tol`` (file units), drop repeated faces, check that the mesh is
    closed and orient its faces outward. SceneError naming the block for an open or
    non-manifold mesh, or one with no volume."""
    import trimesh
    from scipy.spatial import ConvexHull, QhullError

    notes = []
    V, faces, merged = merge_vertices(np.asarray(V, dtype=float), faces, tol)
    if merged:
        notes.append(f"merged {merged} duplicate vertices")
    faces, dup = unique_faces(faces)
    if dup:
        notes.append(f"dropped {dup} repeated faces")
    label = f"block '{name}' ({source})"
    if len(faces) < 4:
        raise SceneError(f"{label}: {len(faces)} faces cannot close a solid")
    from scenes.importers.planes import newell_normal, triangulate

    tri, owner = [], []
    for k, f in enumerate(faces):
        P = V[f]
        n = newell_normal(P)
        if not np.linalg.norm(n) > 0:
            raise SceneError(f"{label}: a face with no area at {P[0].round(6).tolist()}")
        for t in triangulate(P, n / np.linalg.norm(n)):
            tri.append(tuple(f[i] for i in t))
            owner.append(k)
    mesh = trimesh.Trimesh(V, np.array(tri), process=False)
    # each undirected edge must bound exactly two polygons
    edges = {}
    for f in faces:
        for a, b in zip(f, f[1:] + f[:1]):
            e = (min(a, b), max(a, b))
            edges[e] = edges.get(e, 0) + 1
    bad = [e for e, c in edges.items() if c != 2]
    if bad:
        e = bad[0]
        kind = "open (an edge bounds one face)" if edges[e] == 1 else f"not manifold (an edge bounds {edges[e]} faces)"
        raise SceneError(f"{label}: the mesh is {kind} at {V[e[0]].round(6).tolist()}-{V[e[1]].round(6).tolist()}; "
                         f"{len(bad)} such edges")
    if not mesh.is_winding_consistent:
        trimesh.repair.fix_winding(mesh)
        notes.append("made the face orientation consistent")
    vol = float(mesh.volume)
    if vol < 0:
        mesh.invert()
        vol = -vol
        notes.append("turned the faces outward")
    flipped = {}
    for t, k in enumerate(owner):
        if k not in flipped:
            # the polygon's triangles are right-handed about its own loop: a triangle turned
            # by the repair means the polygon is turned
            flipped[k] = tuple(mesh.faces[t]) != tri[t]
    faces = [f[::-1] if flipped[k] else f for k, f in enumerate(faces)]
    face_tris = [[] for _ in faces]
    for t, k in enumerate(owner):
        face_tris[k].append(mesh.faces[t])
    face_tris = [np.array(ft) for ft in face_tris]
    scale = float(np.ptp(V, axis=0).max())
    if not vol > 1e-9 * scale**3:
        raise SceneError(f"{label}: the mesh encloses no volume")
    try:
        hull_vol = float(ConvexHull(V - V.mean(axis=0)).volume)
    except QhullError:
        raise SceneError(f"{label}: the vertices are coplanar (no volume)") from None
    if hull_vol < vol * (1 - 1e-6):
        raise SceneError(f"{label}: the mesh volume {vol:.6g} exceeds its convex hull's {hull_vol:.6g} "
                         "(self-intersecting faces)")
    return Solid(name, source, list(tags), V, faces, vol, hull_vol, notes, face_tris)
