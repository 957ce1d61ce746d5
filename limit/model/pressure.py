"""Pressure loads: a pressure on the faces of blocks that face one direction (docs/formats.md,
'Loads'), uniform or linear with height, as for backfill, water or wind; in 2D a pressure on an
edge times the scene's thickness is a line load.

The pressure at a point at height z (along -gravity, m) is ``p(z) = value + gradient (level -
z)`` (Pa; ``gradient`` in Pa/m, positive when it grows downwards, as water's 9,810 Pa/m), and
none where that is negative (above a water line). It pushes into the face: the force on a face
with outward normal n is ``-int p n dA``, and its moment about the block's centroid c is
``int (x - c) x (-p n) dA``. Each face is cut at the line where p = 0 and integrated exactly:
triangles (3D) with the rule of the three edge midpoints, segments (2D) with Simpson's rule,
both exact for the quadratic integrands.
"""
from __future__ import annotations

import numpy as np

#: a face is loaded when its outward normal is within this angle (rad) of the load's ``face``
ANGLE_TOL = 1e-3


def _clip(poly: np.ndarray, up: np.ndarray, z0: float, below: bool) -> np.ndarray:
    """The part of a convex face polygon (3D, ordered) or segment (2D) at heights z <= z0
    (``below``) or z >= z0 (Sutherland-Hodgman against one plane)."""
    s = (poly @ up - z0) * (1.0 if below else -1.0)  # <= 0: kept
    if np.all(s <= 0):
        return poly
    if np.all(s >= 0):
        return poly[:0]
    if len(poly) == 2:  # a segment
        a, b = poly
        t = s[0] / (s[0] - s[1])
        m = a + t * (b - a)
        return np.array([a, m]) if s[0] <= 0 else np.array([m, b])
    out = []
    for i in range(len(poly)):
        p, q, sp, sq = poly[i], poly[(i + 1) % len(poly)], s[i], s[(i + 1) % len(poly)]
        if sp <= 0:
            out.append(p)
        if (sp < 0 < sq) or (sq < 0 < sp):
            out.append(p + sp / (sp - sq) * (q - p))
    return np.array(out)


def _ordered(face: np.ndarray, n: np.ndarray) -> np.ndarray:
    """A 3D face polygon's vertices ordered around its centre."""
    from limit.geom.geometry import plane_basis

    t1, t2 = plane_basis(n)
    d = face - face.mean(axis=0)
    return face[np.argsort(np.arctan2(d @ t2, d @ t1))]


def _points_weights(poly: np.ndarray, thickness: float):
    """Quadrature points and weights (m^2) on a 3D polygon or a 2D segment (times ``thickness``)."""
    if len(poly) < 2:
        return np.empty((0, poly.shape[1])), np.empty(0)
    if poly.shape[1] == 2:
        a, b = poly[0], poly[-1]
        L = float(np.linalg.norm(b - a))
        return np.array([a, 0.5 * (a + b), b]), thickness * L * np.array([1.0, 4.0, 1.0]) / 6.0
    if len(poly) < 3:
        return np.empty((0, 3)), np.empty(0)
    pts, w = [], []
    for i in range(1, len(poly) - 1):
        a, b, c = poly[0], poly[i], poly[i + 1]
        area = 0.5 * float(np.linalg.norm(np.cross(b - a, c - a)))
        pts += [0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)]
        w += [area / 3.0] * 3
    return np.array(pts), np.array(w)


def resultant(block, ld: dict, up: np.ndarray, thickness: float) -> tuple[np.ndarray, np.ndarray]:
    """(force (d,), moment about the block's centroid (1,) in 2D or (3,)) of a pressure load ``ld``
    ({"face", "value", "gradient", "level"}, module docstring) on ``block``."""
    d = len(up)
    n_sel = np.asarray(ld["face"], dtype=float)
    n_sel = n_sel / np.linalg.norm(n_sel)
    value, grad, level = float(ld["value"]), float(ld.get("gradient", 0.0)), float(ld.get("level", 0.0))
    c = np.asarray(block.centroid, dtype=float)
    F, M = np.zeros(d), np.zeros(1 if d == 2 else 3)
    for poly in block.pieces:
        for n, face in zip(poly.face_normals, poly.faces):
            if float(n @ n_sel) < np.cos(ANGLE_TOL):
                continue
            face = np.asarray(face, dtype=float)
            if d == 3:
                face = _ordered(face, n)
            if grad != 0.0:  # keep where p >= 0: z <= level + value / gradient (gradient > 0)
                face = _clip(face, up, level + value / grad, below=grad > 0)
            elif value <= 0.0:
                continue
            pts, w = _points_weights(face, thickness)
            if not len(w):
                continue
            p = value + grad * (level - pts @ up)
            f = -(w * p)[:, None] * n[None, :]  # (k, d) force of each quadrature point
            F += f.sum(axis=0)
            r = pts - c
            M += (r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]).sum(keepdims=True) if d == 2 else np.cross(r, f).sum(axis=0)
    return F, M
