"""3D running-bond walls that meet: a corner (L), a T-junction and a wall with buttresses, their
courses interlocking.

The main wall runs along x over [0, length], y in [0, T]; a branch (the corner's second wall, the
T's stem, a buttress) stands on its back face (y = T) and runs along +y. In even courses the main
wall runs through and the branch abuts it; in odd courses the branch runs through the main wall's
thickness (from y = 0) and the main wall stops against it. z up; lengths in metres.
"""
from __future__ import annotations

import numpy as np

from limit.errors import SceneError

from .. import builders as B
from . import bonds
from ._common import box3, count, finish, positive


def _assemble(name, title, params, length, branches, courses, L, T, H, mu, density):
    """branches: (label, x0, width, depth beyond the main wall's back face, courses, tags)."""
    ymax = T + max([b[3] for b in branches] + [0.0])
    blocks = [B.base(3, -L, length + L, -L, ymax + L)]
    for c in range(courses):
        z0, z1 = c * H, (c + 1) * H
        through = c % 2 == 1
        gaps = sorted((b[1], b[1] + b[2]) for b in branches if through and c < b[4])
        ends = [0.0] + [e for g in gaps for e in g] + [length]
        k = 0
        for j in range(0, len(ends), 2):
            a, b = ends[j], ends[j + 1]
            if b - a <= 1e-9:
                continue
            for x0, x1, _ in bonds.cut("running", c, a, b, L, T):
                blocks.append(box3(f"c{c}-{k}", [x0, 0.0, z0], [x1, T, z1], tags=["main", f"course-{c}"]))
                k += 1
        for label, bx, bw, bd, bc, tags in branches:
            if c >= bc:
                continue
            y0 = 0.0 if through else T
            for m, (y_a, y_b, _) in enumerate(bonds.cut("running", c + 1, y0, T + bd, L, T)):
                blocks.append(box3(f"{label}-c{c}-{m}", [bx, y_a, z0], [bx + bw, y_b, z1],
                                   tags=list(tags) + [label, f"course-{c}"]))
    if params.get("compound_quoins"):
        blocks = _quoins(blocks, courses)
    sc = B.scene(name, 3, blocks, friction=float(mu), density=float(density), sliding_faces=None)
    return finish(sc, title, params)


def _box_vertices(blk):
    c, h = np.asarray(blk["box"]["center"]), np.asarray(blk["box"]["size"]) / 2
    return [[float(c[0] + sx * h[0]), float(c[1] + sy * h[1]), float(c[2] + sz * h[2])]
            for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def _quoins(blocks, courses):
    """Per course, the corner's two first blocks (wall A's 'c{c}-0' and wall B's 'B-c{c}-0', one of
    them over the corner square) as one compound L-shaped block 'quoin-c{c}'."""
    by_id = {b["id"]: b for b in blocks}
    out, merged = [], set()
    for c in range(courses):
        a, b = by_id[f"c{c}-0"], by_id[f"B-c{c}-0"]
        merged |= {a["id"], b["id"]}
        out.append({"id": f"quoin-c{c}", "parts": [{"vertices": _box_vertices(a)}, {"vertices": _box_vertices(b)}],
                    "tags": ["quoin", "main", "branch", "B", f"course-{c}"]})
    return [b for b in blocks if b["id"] not in merged] + out


def _common(length, height, unit):
    if len(unit) != 3:
        raise SceneError(f"unit: expected (L, W, H) in m, got {unit!r}")
    L, W, H = (positive(f"unit[{k}]", u) for k, u in enumerate(unit))
    Lw, Hw = positive("length", length), positive("height", height)
    nc = round(Hw / H)
    if nc < 1 or abs(nc * H - Hw) > 1e-9 * max(1.0, Hw):
        raise SceneError(f"height: {Hw:g} m is not a whole number of courses of {H:g} m")
    return L, W, H, Lw, nc


def wall_corner(length=2.0, length_b=1.6, height=1.2, unit=(0.4, 0.2, 0.2), compound_quoins=False, mu=0.6,
                density=2000.0, name=None) -> dict:
    """Two walls at a right-angle corner, alternate courses interlocking (3D, running bond).

    length: wall A along x, from the outer corner (m).
    length_b: wall B along +y, from A's back face (m).
    height: a whole number of courses (m).
    unit: (L, W, H): block length, wall thickness and course height (m).
    compound_quoins: in each course the two blocks that meet at the corner become one L-shaped
        compound block 'quoin-c{course}' (two convex parts moving together), tagged 'quoin'.
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: wall A 'c{course}-{k}' tagged 'main'; wall B 'B-c{course}-{k}' tagged 'branch' and 'B';
    all 'course-{course}'. Fixed base 'base'. Loads: self weight, 1 g along +x (live).
    """
    params = dict(length=length, length_b=length_b, height=height, unit=tuple(unit),
                  compound_quoins=bool(compound_quoins), mu=mu, density=density)
    L, W, H, Lw, nc = _common(length, height, unit)
    lb = positive("length_b", length_b)
    return _assemble(name or "wall-corner-3d", "Corner of two walls, interlocking courses", params, Lw,
                     [("B", 0.0, W, lb, nc, ["branch"])], nc, L, W, H, mu, density)


def wall_tee(length=2.4, length_b=1.6, height=1.2, at=None, unit=(0.4, 0.2, 0.2), mu=0.6, density=2000.0,
             name=None) -> dict:
    """A T-junction of two walls, alternate courses of the stem running through (3D, running bond).

    Wall B abuts wall A's back face at x = ``at``; in odd courses it runs through A.
    length: wall A along x (m).
    length_b: wall B along +y beyond A's back face (m).
    at: B's left face (m; default centred).
    height: a whole number of courses (m).
    unit: (L, W, H): block length, wall thickness and course height (m).
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.
    Blocks: as :func:`wall_corner`.
    """
    params = dict(length=length, length_b=length_b, height=height, at=at, unit=tuple(unit), mu=mu,
                  density=density)
    L, W, H, Lw, nc = _common(length, height, unit)
    lb = positive("length_b", length_b)
    x0 = (Lw - W) / 2 if at is None else positive("at", at)
    if x0 < L / 2 or x0 + W > Lw - L / 2:
        raise SceneError(f"at: wall B must stand at least L/2 = {L / 2:g} m inside wall A's ends "
                         f"(0 to {Lw:g} m), got {x0:g} m")
    return _assemble(name or "wall-tee-3d", "T-junction of two walls, interlocking courses", params, Lw,
                     [("B", x0, W, lb, nc, ["branch"])], nc, L, W, H, mu, density)


def buttressed_wall(length=3.2, height=1.6, buttresses=(0.4, 2.4), width=0.4, depth=0.4, buttress_courses=None,
                    unit=(0.4, 0.2, 0.2), mu=0.6, density=2000.0, name=None) -> dict:
    """A wall with buttresses bonded into it in alternate courses (3D, running bond).

    The buttresses stand on the wall's back face (y > T).
    length: of the wall along x (m).
    height: a whole number of courses (m).
    buttresses: each buttress's left face along x (m).
    width: buttress width along x (m).
    depth: how far a buttress stands out from the wall's back face (m).
    buttress_courses: a buttress's height in courses (default the wall's).
    unit: (L, W, H): block length, wall thickness and course height (m).
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.
    Blocks: the wall 'c{course}-{k}' tagged 'main'; buttress j 'buttress{j}-c{course}-{k}' tagged
    'buttress' and 'buttress{j}'; all 'course-{course}'.
    """
    params = dict(length=length, height=height, buttresses=list(buttresses), width=width, depth=depth,
                  buttress_courses=buttress_courses, unit=tuple(unit), mu=mu, density=density)
    L, W, H, Lw, nc = _common(length, height, unit)
    bw, bd = positive("width", width), positive("depth", depth)
    bc = nc if buttress_courses is None else count("buttress_courses", buttress_courses)
    if bc > nc:
        raise SceneError(f"buttress_courses: at most the wall's {nc} courses, got {bc}")
    xs = sorted(float(x) for x in buttresses)
    for j, x in enumerate(xs):
        if x < L / 2 - 1e-9 or x + bw > Lw - L / 2 + 1e-9:
            raise SceneError(f"buttresses[{j}]: must stand at least L/2 = {L / 2:g} m inside the wall's ends, "
                             f"got {x:g} m")
        if j and x < xs[j - 1] + bw + L / 2 - 1e-9:
            raise SceneError(f"buttresses[{j}]: closer than width + L/2 to the previous buttress")
    branches = [(f"buttress{j}", x, bw, bd, bc, ["buttress"]) for j, x in enumerate(xs)]
    return _assemble(name or "wall-buttressed-3d", f"Wall with {len(xs)} buttress(es)", params, Lw, branches,
                     nc, L, W, H, mu, density)
