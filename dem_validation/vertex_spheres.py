"""Host side of the vertex-to-face model: where each block's vertex spheres sit.

A sphere of radius r sits at each vertex v of a convex polyhedron, inset so
that it lies inside the block at distance r w_k from each face plane k through
v: its centre c = v + r d with n_k . d = -w_k (outward unit normals n_k; least
squares when more than three faces meet, then scaled so that n_k . d <= -w_k
for every k).

The weights w_k (:func:`face_weight`) do two jobs:

* One side of every joint is recessed. Two faces in contact have opposite
  normals; the one whose normal points "up" (along a fixed direction e, the
  scene's up tilted slightly so that no joint is exactly perpendicular to it)
  gets w >= 1.4, the other w < 1.1. The recessed side's spheres stay 0.3 r
  or more clear of the other face, so each joint is carried by the corners
  of one block only. With both sets in contact at once, each corner of a
  joint held two coincident springs, and a 3-block stack crept at a steady
  rate above its overturning load instead of toppling (+2 % on alpha).
* A jitter of up to 0.1 breaks a symmetry: with equal weights the sphere of a
  corner resting on an aligned square face sits exactly on that face's
  triangulation diagonal, where YADE's closest-point search may call it an
  edge contact and (edgeCoeff = 0) drop it.

The rounding this makes: every contact point lies r w (m) inside the block's
edges, w <= 1.5.
"""
from __future__ import annotations

import numpy as np

from limit.geom.geometry import polyhedron


#: the recess of the upward side of a joint (in units of r), and the jitter's size
RECESS, JITTER = 0.4, 0.1
#: tilt of the recess direction off the scene's up (a generic direction, so that no face
#: of a typical scene is exactly perpendicular to it)
TILT = np.array([0.0123, 0.0071, 0.0097])


def recess_direction(up) -> np.ndarray:
    """Unit vector e: the scene's up (3,) tilted by TILT."""
    e = np.asarray(up, dtype=float) / np.linalg.norm(up) + TILT
    return e / np.linalg.norm(e)


def face_weight(normal, e) -> float:
    """w of a face with outward unit normal ``normal``: 1 + RECESS when the normal points
    along e (n . e > 0), plus a deterministic jitter in [0, JITTER) from its direction."""
    n = np.round(np.asarray(normal, dtype=float), 6)
    x = float(np.dot(n, [0.7548776662, 0.5698402910, 0.3263964]) + 3.0)
    return 1.0 + RECESS * float(np.dot(normal, e) > 0) + JITTER * ((x * 7.618033988749895) % 1.0)


def inset_directions(vertices, up, r_fit: float) -> np.ndarray:
    """(k, 3) inset vectors d (for r = 1, dimensionless) of the (k, 3) vertices of a convex
    polyhedron: the sphere of radius r at vertex v has its centre at v + r d. ``up``: (3,)
    the scene's up (minus gravity). ValueError unless every sphere of radius ``r_fit`` (m,
    the largest the runs use) lies at least r_fit inside every face plane."""
    P = polyhedron(vertices, check_interior=False)
    v = np.asarray(vertices, dtype=float)
    scale = float(np.ptp(v, axis=0).max())
    tol = 1e-7 * scale
    N, off = P.face_normals, P.face_offsets
    e = recess_direction(up)
    w = np.array([face_weight(n, e) for n in N])
    out = np.empty_like(v)
    for j, x in enumerate(v):
        on = np.abs(N @ x - off) <= tol
        if on.sum() < 3:
            raise ValueError(f"vertex {j} lies on {int(on.sum())} face planes (a convex vertex needs 3)")
        out[j] = _inset(N[on], w[on], x, P.centroid, j)
    depth = off[None, :] - (v + r_fit * out) @ N.T
    for j in np.flatnonzero(~np.all(depth >= r_fit * (1 - 1e-9), axis=1)):
        # a face plane that passes near the vertex but not through it (a short edge, as an
        # imported block's planes leave): the sphere is placed against every plane at once
        out[j] = _inset_all_planes(N, off, w, v[j], r_fit, j)
    depth = off[None, :] - (v + r_fit * out) @ N.T
    if not np.all(depth >= r_fit * (1 - 1e-9)):
        raise ValueError(f"a vertex sphere of radius {r_fit:.3g} m does not fit inside the block")
    return out


def _inset_all_planes(N, off, w, x, r, j) -> np.ndarray:
    """The inset vector d at vertex x (3,) that keeps a sphere of radius r at x + r d at least
    r w_k inside every face plane k (normals N (F, 3), offsets off (F,), weights w (F,)): the LP
    max t subject to N d + t w <= (off - N x) / r, t <= 1, |d_i| <= 100; ValueError when t < 1."""
    from scipy.optimize import linprog

    g = (off - N @ x) / r
    res = linprog(np.r_[0.0, 0.0, 0.0, -1.0], A_ub=np.hstack([N, w[:, None]]), b_ub=g,
                  bounds=[(-100.0, 100.0)] * 3 + [(None, 1.0)], method="highs")
    if res.status != 0 or res.x[3] < 1.0 - 1e-9:
        raise ValueError(f"vertex {j}: no room for its sphere of radius {r:.3g} m")
    return res.x[:3]


def _inset(N, w, x, centroid, j) -> np.ndarray:
    """The inset vector d at vertex x (3,) of the face planes with outward normals N (k, 3) and
    weights w (k,): n_k . d = -w_k in the least-squares sense, else towards the block's centroid
    (many faces, some nearly coplanar, at the vertex), scaled so that n_k . d <= -w_k."""
    d, *_ = np.linalg.lstsq(N, -w, rcond=None)
    s = float(np.min(-(N @ d) / w))  # the nearest face plane, in units of its w
    if not s > 0:
        d = centroid - x
        s = float(np.min(-(N @ d) / w))
    if not s > 0:
        raise ValueError(f"vertex {j}: no inward direction for its sphere")
    return d / min(s, 1.0)
