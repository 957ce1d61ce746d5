"""Euclidean distances between convex hulls of point sets (m): a point to a hull, a hull to a
hull, each the least-squares problem over convex weights solved by scipy's NNLS with the
weights' sums held at one by a heavily weighted row. Used to name gaps in rejections."""
from __future__ import annotations

import numpy as np

#: weight of the rows that hold each set's convex weights at a sum of one, relative to the
#: coordinates' spread (the sums are exact to about 1/WEIGHT^2 of that spread)
WEIGHT = 1e4


def point_to_hull(p, vertices) -> float:
    """Distance (m) from point ``p`` (d,) to the convex hull of ``vertices`` (n, d); 0 inside; inf
    for a point so far out that the least squares overflow (coordinates near 1e308)."""
    p = np.atleast_2d(np.asarray(p, dtype=float))
    v = np.asarray(vertices, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        if not np.isfinite((p - v.mean(axis=0)) ** 2).all():
            return float("inf")
    try:
        return hull_to_hull(p, v)
    except ValueError:  # an overflow inside the least squares
        return float("inf")


def hull_to_hull(va, vb) -> float:
    """Distance (m) between the convex hulls of ``va`` (n, d) and ``vb`` (k, d); 0 where they meet."""
    from scipy.optimize import nnls

    va, vb = np.asarray(va, dtype=float), np.asarray(vb, dtype=float)
    origin = va.mean(axis=0)
    va, vb = va - origin, vb - origin
    w = WEIGHT * max(float(np.abs(np.vstack([va, vb])).max()), 1e-300)
    na, nb, d = len(va), len(vb), va.shape[1]
    A = np.zeros((d + 2, na + nb))
    A[:d, :na], A[:d, na:] = va.T, -vb.T
    A[d, :na], A[d + 1, na:] = w, w
    b = np.zeros(d + 2)
    b[d:] = w
    lam, _ = nnls(A, b, maxiter=50 * (na + nb))
    return float(np.linalg.norm(va.T @ lam[:na] - vb.T @ lam[na:]))


def pieces_distance(pieces_a, pieces_b) -> float:
    """Least distance (m) between two blocks given as lists of convex pieces (geometry.Polytope)."""
    return min(hull_to_hull(pa.vertices, pb.vertices) for pa in pieces_a for pb in pieces_b)


def inside(point, polys, tol: float) -> bool:
    """Whether ``point`` (d,) lies in one of the convex ``polys`` (geometry.Polytope), each face
    plane allowed to pass ``tol`` (m) short of it."""
    p = np.asarray(point, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        return any(float(np.max(poly.face_normals @ p - poly.face_offsets)) <= tol for poly in polys)

