"""Convex block geometry: vertices, faces with outward normals, measure, centroid.

Conventions
-----------
* ``d`` is the dimension (2 or 3). Coordinates in metres.
* 2D: a block is a convex polygon in the (x, y) plane, y up. Its *faces* are its
  edges; each face is stored as its two end points, ordered counter-clockwise
  around the block. ``measure`` is the area in m^2 (the scene multiplies it by
  the out-of-plane thickness to get a volume).
* 3D: a block is a convex polyhedron. Each face is a planar convex polygon whose
  vertices are ordered counter-clockwise seen from outside (right-handed about
  the outward normal). ``measure`` is the volume in m^3.
* Every face satisfies ``normal . x == offset`` for its points and
  ``normal . x <= offset`` for every point of the block.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError
from scipy.spatial.transform import Rotation


class GeometryError(ValueError):
    """A block whose vertices do not define a proper convex polytope."""


@dataclass(frozen=True)
class Polytope:
    """A convex polygon (2D) or polyhedron (3D).

    Attributes
    ----------
    vertices : (nv, d) float array, the corner points.
    face_normals : (nf, d) outward unit normals.
    face_offsets : (nf,) plane offsets, ``normal . x = offset`` on the face.
    faces : list of nf arrays (k_f, d), the face polygons (2 points in 2D).
    measure : area (2D, m^2) or volume (3D, m^3).
    centroid : (d,) centre of the area / volume.
    """

    vertices: np.ndarray
    face_normals: np.ndarray
    face_offsets: np.ndarray
    faces: list
    measure: float
    centroid: np.ndarray

    @property
    def dim(self) -> int:
        return self.vertices.shape[1]


def rotation_matrix(dim: int, angle_deg: float, axis=None) -> np.ndarray:
    """Rotation matrix (d, d) for a box rotation: about z in 2D, about ``axis`` in 3D."""
    a = np.deg2rad(angle_deg)
    if dim == 2:
        c, s = np.cos(a), np.sin(a)
        return np.array([[c, -s], [s, c]])
    axis = np.asarray(axis if axis is not None else (0.0, 0.0, 1.0), dtype=float)
    norm = np.linalg.norm(axis)
    if not np.isfinite(norm) or norm == 0.0:
        raise GeometryError("rotation axis must be a non-zero vector")
    return Rotation.from_rotvec(axis / norm * a).as_matrix()


# Box corners and faces in local +/-1 coordinates.
_BOX3_CORNERS = np.array(
    [[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float
)
# Each face: its local outward normal and corner indices counter-clockwise from outside.
_BOX3_FACES = [
    ((-1, 0, 0), [0, 1, 3, 2]),
    ((1, 0, 0), [4, 6, 7, 5]),
    ((0, -1, 0), [0, 4, 5, 1]),
    ((0, 1, 0), [2, 3, 7, 6]),
    ((0, 0, -1), [0, 2, 6, 4]),
    ((0, 0, 1), [1, 5, 7, 3]),
]


def box(center, size, rotation=None) -> Polytope:
    """Rectangle (2D) or rectangular box (3D) of full edge lengths ``size``.

    ``rotation`` is a (d, d) matrix applied about the centre (or None).
    """
    c = np.asarray(center, dtype=float)
    h = 0.5 * np.asarray(size, dtype=float)
    dim = c.size
    R = np.eye(dim) if rotation is None else np.asarray(rotation, dtype=float)
    if dim == 2:
        local = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float) * h
        verts = local @ R.T + c  # counter-clockwise: R is a proper rotation
        return _polygon_from_ccw(verts)
    verts = (_BOX3_CORNERS * h) @ R.T + c
    normals = np.array([n for n, _ in _BOX3_FACES], dtype=float) @ R.T
    faces = [verts[idx] for _, idx in _BOX3_FACES]
    offsets = np.einsum("ij,ij->i", normals, np.array([f[0] for f in faces]))
    return Polytope(verts, normals, offsets, faces, float(np.prod(2 * h)), c.copy())


def _centred_hull(points, tol, n_min: int, few: str, flat: str):
    """(points (n, d), their largest extent, the on-hull tolerance (default 1e-9 x extent), their
    mean o, the convex hull of points - o): centred, for accurate normals far from the origin.
    GeometryError ``few`` for fewer than ``n_min`` points or no extent, ``flat`` when Qhull finds
    no full-dimensional hull."""
    pts = np.asarray(points, dtype=float)
    scale = float(np.ptp(pts, axis=0).max()) if len(pts) else 0.0
    tol = 1e-9 * max(scale, 1e-300) if tol is None else tol
    if len(pts) < n_min or scale <= 0:
        raise GeometryError(few)
    o = pts.mean(axis=0)
    try:
        hull = ConvexHull(pts - o)
    except QhullError:
        raise GeometryError(flat) from None
    return pts, scale, tol, o, hull


def polygon(points, tol: float | None = None, check_interior: bool = True) -> Polytope:
    """Convex polygon, the convex hull of ``points`` (n, 2).

    Raises GeometryError for collinear or repeated points and, when
    ``check_interior``, for points strictly inside the hull (a non-convex
    outline). ``tol`` is the length below which a point counts as on the hull.
    """
    pts, scale, tol, o, hull = _centred_hull(points, tol, 3, "needs at least three distinct vertices",
                                             "vertices are collinear (the polygon has no area)")
    if hull.volume <= (1e-12 * scale) * scale:
        raise GeometryError("vertices are collinear (the polygon has no area)")
    if check_interior:
        _reject_interior_points(pts, hull.equations, tol, o)
    verts = pts[hull.vertices]  # counter-clockwise in 2D
    return _polygon_from_ccw(verts)


def _polygon_from_ccw(verts: np.ndarray) -> Polytope:
    o = verts.mean(axis=0)  # local origin: keeps the shoelace sums accurate far from (0, 0)
    nxt = np.roll(verts, -1, axis=0)
    edge = nxt - verts
    lengths = np.linalg.norm(edge, axis=1)
    keep = lengths > 1e-14 * lengths.max()
    verts, nxt, edge, lengths = verts[keep], nxt[keep], edge[keep], lengths[keep]
    normals = np.column_stack([edge[:, 1], -edge[:, 0]]) / lengths[:, None]
    offsets = np.einsum("ij,ij->i", normals, verts)
    area, centroid = polygon_area_centroid(verts - o)
    centroid = o + centroid
    faces = [np.array([a, b]) for a, b in zip(verts, nxt)]
    return Polytope(verts, normals, offsets, faces, float(area), centroid)


def polyhedron(points, tol: float | None = None, check_interior: bool = True) -> Polytope:
    """Convex polyhedron, the convex hull of ``points`` (n, 3).

    Coplanar hull triangles are merged into one polygonal face. Raises
    GeometryError for coplanar points and, when ``check_interior``, for points
    strictly inside the hull.
    """
    pts, scale, tol, o, hull = _centred_hull(points, tol, 4, "needs at least four vertices that are not coplanar",
                                             "vertices are coplanar (the block has no volume)")
    if hull.volume <= 1e-12 * scale**3:
        raise GeometryError("vertices are coplanar (the block has no volume)")
    if check_interior:
        _reject_interior_points(pts, hull.equations, tol, o)

    eq = hull.equations  # (nt, 4): n . x + c <= 0 inside
    # Group hull triangles lying in the same plane.
    same = (eq[:, None, :3] * eq[None, :, :3]).sum(-1) > 1.0 - 1e-9
    same &= np.abs(eq[:, None, 3] - eq[None, :, 3]) <= tol
    label = -np.ones(len(eq), dtype=int)
    n_faces = 0
    for i in range(len(eq)):
        if label[i] < 0:
            label[same[i] & (label < 0)] = n_faces
            n_faces += 1

    used = np.unique(hull.simplices)
    normals, offsets, faces = [], [], []
    for f in range(n_faces):
        tri = np.flatnonzero(label == f)
        n = eq[tri, :3].mean(axis=0)
        n /= np.linalg.norm(n)
        idx = np.unique(hull.simplices[tri])
        p = pts[idx]
        e1, e2 = plane_basis(n)
        rel = p - p.mean(axis=0)
        ang = np.arctan2(rel @ e2, rel @ e1)  # counter-clockwise about n
        poly = p[np.argsort(ang)]
        normals.append(n)
        offsets.append(float(poly.mean(axis=0) @ n))  # on the original coordinates
        faces.append(poly)
    verts = pts[used]

    # Volume and centroid from tetrahedra on the hull triangles.
    tri = pts[hull.simplices] - o
    vol6 = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))
    vol6 = np.abs(vol6)
    volume = vol6.sum() / 6.0
    centroid = o + (vol6[:, None] * tri.sum(axis=1)).sum(axis=0) / (4.0 * vol6.sum())
    return Polytope(verts, np.array(normals), np.array(offsets), faces, float(volume), centroid)


def _reject_interior_points(pts: np.ndarray, equations: np.ndarray, tol: float, origin) -> None:
    """Raise if a given point lies strictly inside the hull (non-convex outline).
    ``equations`` are Qhull's facet planes for the points shifted by ``-origin``."""
    dist = (pts - origin) @ equations[:, :-1].T + equations[:, -1]  # <= 0 inside
    depth = -dist.max(axis=1)  # distance inside the hull; 0 on the boundary
    bad = np.flatnonzero(depth > tol)
    if bad.size:
        i = int(bad[0])
        raise GeometryError(
            f"vertex {i} {pts[i].tolist()} lies inside the hull of the others: "
            "the vertex set is not convex"
        )


def plane_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (e1, e2) with e1 x e2 = n, for a unit normal n (3,) or unit
    normals n (m, 3) (then e1, e2 are (m, 3))."""
    n = np.asarray(n, dtype=float)
    a = np.eye(3)[np.argmin(np.abs(n), axis=-1)]
    e1 = np.cross(a, n)
    if e1.ndim == 1:
        e1 /= np.linalg.norm(e1)
    else:
        e1 /= np.linalg.norm(e1, axis=-1)[..., None]
    e2 = np.cross(n, e1)
    return e1, e2


def polygon_area_centroid(P) -> tuple:
    """Signed area and centroid of polygons by the shoelace formula.

    ``P`` (k, 2), or a stack (..., k, 2) of polygons with the same vertex count; the
    area is positive for counter-clockwise vertices. Returns (area, centroid): a float
    and a (2,) array, or arrays (...,) and (..., 2). Far from (0, 0), pass coordinates
    relative to a nearby point (e.g. the vertex mean) and add it back to the centroid.
    """
    P = np.asarray(P, dtype=float)
    x, y = P[..., 0], P[..., 1]
    xn, yn = np.roll(x, -1, axis=-1), np.roll(y, -1, axis=-1)
    cr = x * yn - xn * y  # twice the signed area of the triangle (0, p_i, p_i+1)
    a = 0.5 * cr.sum(axis=-1)
    c = np.stack([((x + xn) * cr).sum(axis=-1), ((y + yn) * cr).sum(axis=-1)], axis=-1) / (6 * np.asarray(a)[..., None])
    return (float(a), c) if P.ndim == 2 else (a, c)


def polytope(points, dim: int, tol: float | None = None) -> Polytope:
    """Convex hull of ``points`` as a polygon (dim 2) or polyhedron (dim 3)."""
    return polygon(points, tol) if dim == 2 else polyhedron(points, tol)


def envelope(parts: list[Polytope]) -> Polytope:
    """The rigid union of convex ``parts`` (a compound block): the convex hull of their vertices,
    carrying the union's measure (the sum of the parts', which must not overlap) and its
    centroid (the measure-weighted mean of the parts' centroids). The hull's faces bound the
    block's extent (bounding box, broad phase, sizes); contacts, drawings and the DEM use the
    parts themselves."""
    if len(parts) == 1:
        return parts[0]
    pts = np.vstack([p.vertices for p in parts])
    hull = (polygon if parts[0].dim == 2 else polyhedron)(pts, check_interior=False)
    m = np.array([p.measure for p in parts])
    c = (m[:, None] * np.array([p.centroid for p in parts])).sum(axis=0) / m.sum()
    return Polytope(hull.vertices, hull.face_normals, hull.face_offsets, hull.faces, float(m.sum()), c)
