"""Host side of the vertex-to-face model: where each block's vertex spheres sit.

A sphere of radius r sits at each vertex v of a convex polyhedron, inset so
that it lies inside the block and touches (to within the weights below) the
face planes through v: its centre c = v + r d with n_k . d = -w_k for the
faces k through v (outward unit normals n_k; least squares when more than
three faces meet, then scaled so that n_k . d <= -w_k for every k).

The weights w_k in [1, 1.2), one per face direction, break a symmetry: with
w = 1 the sphere of a corner resting on an aligned square face would sit
exactly on that face's triangulation diagonal, where YADE's closest-point
search may call it an edge contact and (edgeCoeff = 0) drop it. The rounding
this makes: every contact point lies r w (m) inside the block's edges.
"""
from __future__ import annotations

import numpy as np

from limit.geometry import polyhedron


def face_weight(normal) -> float:
    """w in [1, 1.2) from the direction of an outward unit normal (deterministic)."""
    n = np.round(np.asarray(normal, dtype=float), 6)
    x = float(np.dot(n, [0.7548776662, 0.5698402910, 0.3263964]) + 3.0)
    return 1.0 + 0.2 * ((x * 7.618033988749895) % 1.0)


def inset_directions(vertices) -> np.ndarray:
    """(k, 3) inset vectors d (for r = 1, dimensionless) of the (k, 3) vertices of a convex
    polyhedron: the sphere of radius r at vertex v has its centre at v + r d."""
    P = polyhedron(vertices, check_interior=False)
    v = np.asarray(vertices, dtype=float)
    scale = float(np.ptp(v, axis=0).max())
    tol = 1e-7 * scale
    N, off = P.face_normals, P.face_offsets
    w = np.array([face_weight(n) for n in N])
    out = np.empty_like(v)
    for j, x in enumerate(v):
        on = np.abs(N @ x - off) <= tol
        if on.sum() < 3:
            raise ValueError(f"vertex {j} lies on {int(on.sum())} face planes (a convex vertex needs 3)")
        d, *_ = np.linalg.lstsq(N[on], -w[on], rcond=None)
        s = float(np.min(-(N[on] @ d) / w[on]))  # the nearest face plane, in units of its w
        if not s > 0:
            raise ValueError(f"vertex {j}: no inward direction for its sphere")
        d /= min(s, 1.0)
        out[j] = d
    return out


def check_fit(vertices, dirs, r: float) -> None:
    """ValueError unless every sphere (centre v + r d) lies at least r inside every face plane."""
    P = polyhedron(vertices, check_interior=False)
    centres = np.asarray(vertices, dtype=float) + r * np.asarray(dirs)
    depth = P.face_offsets[None, :] - centres @ P.face_normals.T
    if not np.all(depth >= r * (1 - 1e-9)):
        raise ValueError(f"a vertex sphere of radius {r:.3g} m does not fit inside the block")
