"""Shared pieces of the generators: parameter checks, blocks from outlines and half-spaces.

Axes: 2D x horizontal, y up; 3D x along the structure, y across it, z up. Lengths in metres.
"""
from __future__ import annotations

import math

import numpy as np

from limit.errors import SceneError

from .. import builders as B


def positive(name: str, value, *, allow_zero: bool = False) -> float:
    """``value`` as a float, or a SceneError naming the parameter ``name``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise SceneError(f"{name}: must be {'>= 0' if allow_zero else '> 0'}, got {value!r}")
    return v


def count(name: str, value, minimum: int = 1) -> int:
    """``value`` as an int >= ``minimum``, or a SceneError naming the parameter."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise SceneError(f"{name}: must be a whole number >= {minimum}, got {value!r}")
    return int(value)


def choice(name: str, value, options) -> str:
    if value not in options:
        raise SceneError(f"{name}: must be one of {', '.join(options)}, got {value!r}")
    return value


def dimension(dim) -> int:
    if dim not in (2, 3):
        raise SceneError(f"dim: must be 2 or 3, got {dim!r}")
    return int(dim)


def outline_block(bid, pts, dim, y0=0.0, y1=None, fixed=False, tags=()):
    """A block from a convex outline in the (x, up) plane: the polygon in 2D, or the prism
    over y in [y0, y1] in 3D. An axis-aligned rectangle is written as a ``box``."""
    pts = np.asarray(pts, dtype=float)
    kw = {"tags": list(tags)} if tags else {}
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    on_edge = lambda p: all(min(abs(p[k] - lo[k]), abs(p[k] - hi[k])) < 1e-12 for k in (0, 1))
    rect = len(pts) == 4 and all(on_edge(p) for p in pts) and len({(round(p[0], 9), round(p[1], 9)) for p in pts}) == 4
    if dim == 2:
        if rect:
            return B.box_block(bid, (lo + hi) / 2, hi - lo, fixed=fixed, **kw)
        return B.vertex_block(bid, pts, fixed=fixed, **kw)
    if rect:
        return B.box_block(bid, [(lo[0] + hi[0]) / 2, (y0 + y1) / 2, (lo[1] + hi[1]) / 2],
                           [hi[0] - lo[0], y1 - y0, hi[1] - lo[1]], fixed=fixed, **kw)
    v = [[x, y, z] for y in (y0, y1) for x, z in pts]
    return B.vertex_block(bid, v, fixed=fixed, **kw)


def box3(bid, lo, hi, fixed=False, tags=()):
    """An axis-aligned 3D box from its lower and upper corners (m)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    kw = {"tags": list(tags)} if tags else {}
    return B.box_block(bid, (lo + hi) / 2, hi - lo, fixed=fixed, **kw)


def halfspace_vertices(A, b, interior) -> np.ndarray:
    """Vertices of the bounded convex polyhedron {x : A x <= b} (3D), ``interior`` a point inside."""
    from scipy.spatial import ConvexHull, HalfspaceIntersection

    A, b = np.asarray(A, float), np.asarray(b, float)
    hs = HalfspaceIntersection(np.column_stack([A, -b]), np.asarray(interior, float))
    pts = hs.intersections
    hull = ConvexHull(pts)
    pts = pts[hull.vertices]
    # merge near-duplicates (several planes through one vertex)
    scale = float(np.ptp(pts, axis=0).max())
    out = []
    for p in pts:
        if not any(np.linalg.norm(p - q) < 1e-9 * scale for q in out):
            out.append(p)
    return np.array(out)


def finish(scene: dict, title: str, params: dict) -> dict:
    """Check the material parameters and record the generator and its parameters under ``meta``."""
    positive("mu", params.get("mu", 0.0), allow_zero=True)
    positive("density", params.get("density", 1.0))
    scene.setdefault("meta", {})
    scene["meta"].setdefault("title", title)
    scene["meta"]["generator"] = {k: (list(v) if isinstance(v, tuple) else v) for k, v in params.items()}
    return scene
