"""Intersection of convex polygons with a length tolerance, vectorised over many pairs.

Why not shapely's overlay: contact faces of masonry blocks very often have
edges on (nearly) the same line, and an overlay computes the crossing of two
nearly parallel segments, which is ill-conditioned: the spurious vertex can sit
anywhere along the shared line (seen here: 1e-6 of the face size off on a
scene far from the origin). Here a crossing is computed only for segments whose
end points lie on opposite sides of the other's line by more than ``tol``;
points within ``tol`` of a line count as on it. Every vertex of the result is
then a vertex of one polygon inside the other, or a well-conditioned crossing.
"""
from __future__ import annotations

import numpy as np


def _edges(P):
    """Start points, unit inward normals and edge vectors of CCW polygons P (m, k, 2)."""
    E = np.roll(P, -1, axis=1) - P
    L = np.linalg.norm(E, axis=2, keepdims=True)
    inward = np.stack([-E[..., 1], E[..., 0]], axis=-1) / np.where(L > 0, L, 1.0)
    return inward, E


def intersect(A: np.ndarray, B: np.ndarray, tol: float):
    """Intersections of counter-clockwise convex polygons A (m, ka, 2) and B (m, kb, 2).

    Returns a list of m arrays (k_i, 2): the intersection polygon's vertices,
    counter-clockwise, near-duplicates (closer than ``tol``) removed; an array
    with fewer than three points means no area.
    """
    m, ka, _ = A.shape
    kb = B.shape[1]
    nA, EA = _edges(A)
    nB, EB = _edges(B)
    # dBA[r, j, i]: signed distance of B_j from A's edge line i (>= 0 inside A).
    dBA = np.einsum("rid,rjid->rji", nA, B[:, :, None, :] - A[:, None, :, :])
    dAB = np.einsum("rjd,rijd->rij", nB, A[:, :, None, :] - B[:, None, :, :])
    b_in = dBA.min(axis=2) >= -tol
    a_in = dAB.min(axis=2) >= -tol
    # Crossing of A-edge i with B-edge j.
    s0 = np.transpose(dBA, (0, 2, 1))                  # (r, i, j): B_j from A-line i
    s1 = np.roll(s0, -1, axis=2)                       # B_{j+1} from A-line i
    r0 = dAB                                           # (r, i, j): A_i from B-line j
    r1 = np.roll(r0, -1, axis=1)                       # A_{i+1} from B-line j
    proper = (((s0 > tol) & (s1 < -tol)) | ((s0 < -tol) & (s1 > tol))) & \
             (((r0 > tol) & (r1 < -tol)) | ((r0 < -tol) & (r1 > tol)))
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(proper, s0 / (s0 - s1), 0.0)
    X = B[:, None, :, :] + frac[..., None] * EB[:, None, :, :]  # (r, i, j, 2)
    pts = np.concatenate([A, B, X.reshape(m, ka * kb, 2)], axis=1)
    ok = np.concatenate([a_in, b_in, proper.reshape(m, ka * kb)], axis=1)

    out = []
    for r in range(m):
        p = pts[r, ok[r]]
        if len(p) < 3:
            out.append(p)
            continue
        c = p.mean(axis=0)
        p = p[np.argsort(np.arctan2(p[:, 1] - c[1], p[:, 0] - c[0]))]
        keep = np.linalg.norm(p - np.roll(p, 1, axis=0), axis=1) > tol
        if not keep.any():
            keep[0] = True
        out.append(p[keep])
    return out
