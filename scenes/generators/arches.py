"""Arches on piers: semicircular, pointed and segmental voussoir arches whose springing joints rest
on skewbacks, the top course of two piers of stacked blocks.

2D: x horizontal (the arch is symmetric about x = 0), y up. 3D: the same outlines extruded along y
over [0, depth], z up. The piers stand on a fixed base whose top is at height 0. Lengths in metres.
"""
from __future__ import annotations

import math

import numpy as np

from limit.errors import SceneError

from .. import builders as B
from ._common import choice, count, dimension, finish, outline_block, positive

KINDS = ("semicircular", "pointed", "segmental")


def arch_joints(kind="semicircular", span=2.0, thickness=0.25, n=11, rise=None, radius=None,
                spring=1.0) -> np.ndarray:
    """The joints of the arch ring, (n + 1, 2, 2): joint k as its (intrados, extrados) end points
    [x, y] in m, from the right springing (k = 0) to the left one (k = n); voussoir k lies between
    joints k and k + 1. ``spring`` is the height of the intrados springing points (m).

    semicircular: intrados radius span/2, centre (0, spring), joints radial and equally spaced in
    angle. segmental: intrados through (+-span/2, spring) with ``rise`` (default span/4), radial joints
    equally spaced in angle. pointed (two-centred; n even): each half an arc of intrados radius
    ``radius`` (default span: equilateral) centred on the springing line at distance ``radius`` from
    its own springing point, n/2 radial joints equally spaced in angle and a vertical crown joint."""
    s, t = span, thickness
    if kind == "semicircular":
        ri, c, phi0 = s / 2, (0.0, spring), 0.0
    elif kind == "segmental":
        f = s / 4 if rise is None else rise
        if not 0 < f < s / 2:
            raise SceneError(f"rise: a segmental arch needs 0 < rise < span/2 = {s / 2:g} m, got {f!r}")
        ri = (s * s / 4 + f * f) / (2 * f)
        c = (0.0, spring + f - ri)
        phi0 = math.asin((spring - c[1]) / ri)
    else:
        if n % 2:
            raise SceneError(f"n: a pointed arch needs an even number of voussoirs (a vertical crown joint), got {n}")
        r = s if radius is None else radius
        if r <= s / 2:
            raise SceneError(f"radius: a pointed arch needs radius > span/2 = {s / 2:g} m, got {r!r}")
        cx = s / 2 - r  # centre of the right half (the left half mirrors it)
        th_i = math.acos(-cx / r)          # intrados meets x = 0
        th_e = math.acos(-cx / (r + t))    # extrados meets x = 0
        half = n // 2
        right = []
        for k in range(half):
            a = k * th_i / half
            right.append([[cx + r * math.cos(a), spring + r * math.sin(a)],
                          [cx + (r + t) * math.cos(a), spring + (r + t) * math.sin(a)]])
        crown = [[0.0, spring + r * math.sin(th_i)], [0.0, spring + (r + t) * math.sin(th_e)]]
        left = [[[-p[0], p[1]] for p in j] for j in reversed(right)]
        return np.array(right + [crown] + left)
    re = ri + t
    phis = np.linspace(phi0, math.pi - phi0, n + 1)
    return np.array([[[c[0] + ri * math.cos(p), c[1] + ri * math.sin(p)],
                      [c[0] + re * math.cos(p), c[1] + re * math.sin(p)]] for p in phis])


def arch(kind="semicircular", span=2.0, thickness=0.25, n=None, rise=None, radius=None, pier_height=1.5,
         pier_width=0.5, pier_courses=3, fixed_piers=False, dim=2, depth=None, mu=0.8, density=2000.0,
         name=None) -> dict:
    """A voussoir arch on two piers with skewbacks; returns a ``blockscene/1`` dict.

    kind: 'semicircular', 'pointed' or 'segmental'.
    span: clear span between the piers' inner faces (m).
    thickness: ring thickness, measured along the joints (m).
    n: voussoirs (even for a pointed arch; default 11, and 12 for a pointed arch).
    rise: segmental arch only, the intrados rise above the springing (m; default span/4).
    radius: pointed arch only, the intrados radius of each half (m; default span, equilateral).
    pier_height: height of the intrados springing above the base (m).
    pier_width: pier width along x (m; at least the ring's horizontal extent at the springing).
    pier_courses: blocks in each pier, the skewback (top course) included.
    fixed_piers: the piers and skewbacks are one fixed block each (an arch between abutments).
    dim: 2 or 3.
    depth: 3D only, the extrusion along y (m; default the thickness).
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: voussoirs 'v0' (right) to 'v{n-1}' (left), tagged 'voussoir' and 'ring', the two at
    the skewbacks also 'springing', the crown one(s) 'key'; piers 'pier-right-k', 'pier-left-k'
    (k = 0 at the base) tagged 'pier', 'pier-right'/'pier-left' and 'course-k', the top one named
    'skewback-right'/'skewback-left' and tagged 'skewback'; the fixed base 'base'.
    Loads: self weight (dead), a body force of 1 g along +x (live).
    """
    params = dict(kind=kind, span=span, thickness=thickness, n=n, rise=rise, radius=radius,
                  pier_height=pier_height, pier_width=pier_width, pier_courses=pier_courses,
                  fixed_piers=fixed_piers, dim=dim, depth=depth, mu=mu, density=density)
    choice("kind", kind, KINDS)
    dim = dimension(dim)
    s, t = positive("span", span), positive("thickness", thickness)
    n = count("n", (12 if kind == "pointed" else 11) if n is None else n, 3 if kind != "pointed" else 2)
    hp = positive("pier_height", pier_height)
    w = positive("pier_width", pier_width)
    nc = count("pier_courses", pier_courses)
    depth = t if depth is None else positive("depth", depth)
    if rise is not None:
        positive("rise", rise)
    if radius is not None:
        positive("radius", radius)
    J = arch_joints(kind, s, t, n, rise, radius, spring=hp)
    ext = J[0, 1]
    if ext[0] > s / 2 + w + 1e-12:
        raise SceneError(f"pier_width: the springing joint reaches x = {ext[0]:.4g} m, beyond the pier "
                         f"({s / 2 + w:.4g} m): pier_width must be >= {ext[0] - s / 2:.4g} m")
    h_course = hp / nc
    blocks = [B.base(dim, -s / 2 - 2 * w, s / 2 + 2 * w, -depth, 2 * depth)]
    # Pier k of side +-1: x from s/2 to s/2 + w (mirrored), courses of equal height up to the
    # springing; the top course (the skewback) ends in the springing joint and a level top.
    for side, sname in ((1, "right"), (-1, "left")):
        x_in, x_out = s / 2, s / 2 + w
        I, E = J[0] if side == 1 else (J[-1] * [[-1, 1], [-1, 1]])
        I, E = np.asarray(I), np.asarray(E)

        def mirror(pts):
            return [[side * p[0], p[1]] for p in pts]

        top = [[x_out, E[1]], E.tolist(), I.tolist()] if E[1] > I[1] + 1e-12 else [[x_out, hp], [x_in, hp]]
        if fixed_piers:
            pts = [[x_in, 0.0], [x_out, 0.0]] + top
            blocks.append(outline_block(f"pier-{sname}", _ccw(mirror(pts)), dim, 0.0, depth, fixed=True,
                                        tags=["pier", f"pier-{sname}", "skewback"]))
            continue
        for k in range(nc):
            z0 = k * h_course
            if k < nc - 1:
                pts = [[x_in, z0], [x_out, z0], [x_out, z0 + h_course], [x_in, z0 + h_course]]
                bid, tags = f"pier-{sname}-{k}", ["pier", f"pier-{sname}", f"course-{k}"]
            else:
                pts = [[x_in, z0], [x_out, z0]] + top
                bid, tags = f"skewback-{sname}", ["pier", f"pier-{sname}", f"course-{k}", "skewback"]
            blocks.append(outline_block(bid, _ccw(mirror(pts)), dim, 0.0, depth, tags=tags))
    key = {n // 2} if n % 2 else {n // 2 - 1, n // 2}
    for k in range(n):
        quad = [J[k, 0], J[k, 1], J[k + 1, 1], J[k + 1, 0]]
        tags = ["voussoir", "ring"] + (["springing"] if k in (0, n - 1) else []) + (["key"] if k in key else [])
        blocks.append(outline_block(f"v{k}", _ccw(quad), dim, 0.0, depth, tags=tags))
    sc = B.scene(name or f"arch-{kind}-{n}-on-piers-{dim}d", dim, blocks, friction=float(mu),
                 density=float(density), sliding_faces=None)
    return finish(sc, f"{kind.capitalize()} arch of {n} voussoirs on piers", params)


def _ccw(pts):
    """Distinct points of a convex outline, counter-clockwise."""
    P = np.asarray(pts, dtype=float)
    keep = [P[0]]
    for p in P[1:]:
        if np.linalg.norm(p - keep[-1]) > 1e-12 and np.linalg.norm(p - keep[0]) > 1e-12:
            keep.append(p)
    P = np.array(keep)
    c = P.mean(axis=0)
    order = np.argsort(np.arctan2(P[:, 1] - c[1], P[:, 0] - c[0]))
    return P[order].tolist()
