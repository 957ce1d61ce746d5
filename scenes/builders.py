"""Scene builders: functions that return ``blockscene/1`` dicts (docs/formats.md, 'Scene file').

Axes: 2D x horizontal, y up; 3D x along the wall, y across it, z up.
All lengths in metres. Every builder puts a fixed base (or fixed supports)
under the structure and, unless told otherwise, loads it with its self weight
(dead) and a horizontal body force of 1 g along +x (live).
"""
from __future__ import annotations

import math

import numpy as np

FORMAT = "blockscene/1"


def scene(name, dim, blocks, *, friction=0.6, density=2000.0, live=None, dead=None,
          thickness=None, expected=None, meta=None, friction_pairs=None, sliding_faces=4, **extra) -> dict:
    """Assemble a scene dict. ``live`` defaults to a +x body force of 1 g on all blocks.
    ``sliding_faces`` (3D): the friction model the scene declares; the builders keep the
    paper's 4 faces (circumscribed: exact along the interface axes), so that the catalog
    stays a reproduction and its closed forms are those of the paper's model (None: the
    solver's default, 24 inscribed faces)."""
    if live is None:
        live = [{"type": "body_force", "direction": [1.0] + [0.0] * (dim - 1)}]
    out = {"format": FORMAT, "name": name, "dim": dim, "friction": friction, "density": density}
    if thickness is not None:
        out["thickness"] = thickness
    out["blocks"] = blocks
    if dim == 3 and sliding_faces is not None:
        out["interfaces"] = {"sliding_faces": int(sliding_faces)}
    if friction_pairs:
        out.setdefault("interfaces", {})["friction"] = [{"blocks": list(p), "mu": mu}
                                                        for p, mu in friction_pairs.items()]
    out["loads"] = {"dead": dead if dead is not None else [{"type": "self_weight"}], "live": live}
    if expected:
        out["expected"] = expected
    if meta:
        out["meta"] = meta
    out.update(extra)
    return out


def box_block(bid, center, size, fixed=False, **kw) -> dict:
    blk = {"id": bid, "box": {"center": [float(c) for c in center], "size": [float(s) for s in size]}}
    if fixed:
        blk["fixed"] = True
    blk.update(kw)
    return blk


def vertex_block(bid, vertices, fixed=False, **kw) -> dict:
    blk = {"id": bid, "vertices": [[float(c) for c in v] for v in np.asarray(vertices)]}
    if fixed:
        blk["fixed"] = True
    blk.update(kw)
    return blk


def base(dim, x0, x1, y0=0.0, y1=None, depth=0.2, bid="base") -> dict:
    """A fixed slab whose top is at height 0, spanning [x0, x1] (and [y0, y1] in 3D)."""
    if dim == 2:
        return box_block(bid, [(x0 + x1) / 2, -depth / 2], [x1 - x0, depth], fixed=True)
    return box_block(bid, [(x0 + x1) / 2, (y0 + y1) / 2, -depth / 2], [x1 - x0, y1 - y0, depth], fixed=True)


def _place(dim, bid, x0, x1, z0, z1, y0=0.0, y1=0.0, **kw):
    if dim == 2:
        return box_block(bid, [(x0 + x1) / 2, (z0 + z1) / 2], [x1 - x0, z1 - z0], **kw)
    return box_block(bid, [(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2], [x1 - x0, y1 - y0, z1 - z0], **kw)


# ----------------------------------------------------------------------------
# Closed-form cases


def single_block(dim=2, b=0.3, h=1.0, t=None, mu=0.6, name=None, **kw) -> dict:
    """One free block b (along x) by h (up) [by t across, 3D] on a fixed base."""
    t = b if t is None else t
    blocks = [base(dim, -b, 2 * b, -t, 2 * t),
              _place(dim, "block", 0.0, b, 0.0, h, 0.0, t)]
    return scene(name or f"single-block-{dim}d", dim, blocks, friction=mu, **kw)


def confined_block(dim=2, b=0.4, h=1.0, t=None, mu=0.5, name=None, **kw) -> dict:
    """One free block b (along x) by h (up) [by t across] between a fixed floor and a fixed
    ceiling that touches its top."""
    t = b if t is None else t
    ceiling = _place(dim, "ceiling", -b, 2 * b, h, h + 0.2, -t, 2 * t)
    ceiling["fixed"] = True
    blocks = [base(dim, -b, 2 * b, -t, 2 * t), _place(dim, "block", 0.0, b, 0.0, h, 0.0, t), ceiling]
    return scene(name or f"confined-block-{dim}d", dim, blocks, friction=mu, **kw)


def confined_block_alpha(b: float, h: float, mu: float) -> float:
    """Frictional collapse factor of :func:`confined_block` under a horizontal body force at
    its centroid, self weight W as dead load, when b < mu h (derivation: issue 20).

    The block translates, sliding on both faces: floor N1 = W + N2 (up), ceiling N2 (down),
    friction mu N1 and mu N2 both against the motion, so alpha W = mu (W + 2 N2). About the
    centroid the two friction forces leave the moment mu (N1 - N2) h/2 = mu W h/2, which the
    normal forces can resist at most by (N1 + N2) b/2 (each at an outer corner): N2 >=
    W (mu h / b - 1) / 2, hence alpha = mu^2 h / b. With b >= mu h no ceiling force is
    needed and alpha = mu. The associative LP has no mechanism (sliding dilates, the ceiling
    forbids it): it is unbounded."""
    return mu * mu * h / b if b < mu * h else mu


def eccentric_slab(e=0.25, b=1.0, h=0.1, mu=0.6, density=2000.0, name=None, **kw) -> dict:
    """A flat square slab b x b (m, plan) by h (up) on a fixed base (3D): self weight W as the dead
    load, and as the live load a horizontal force W along +x at its centroid's height, ``e`` (m)
    off its centre along +y. The 24 inscribed sliding faces are the scene's friction model.
    Collapse by sliding and twisting at once: :func:`eccentric_slab_alpha`."""
    w = density * b * b * h * 9.81
    blocks = [base(3, -b / 2, 2 * b, -b / 2, 2 * b), _place(3, "slab", 0.0, b, 0.0, h, 0.0, b)]
    live = [{"type": "point_force", "block": "slab", "force": [w, 0.0, 0.0],
             "point": [b / 2, b / 2 + e, h / 2]}]
    return scene(name or "eccentric-slab-3d", 3, blocks, friction=mu, density=density, live=live,
                 sliding_faces=None, **kw)


def eccentric_slab_alpha(e: float, b: float = 1.0, mu: float = 0.6) -> float:
    """Collapse factor of :func:`eccentric_slab` on four corner contacts (+-a, +-a), a = b / 2,
    about its centre, each with N = W / 4 (a flat slab's elastic contacts share the weight
    equally) and a circular Coulomb cone.

    The slab turns about a centre (0, c): mirroring x -> -x and reversing the motion gives the
    same problem, so the centre lies on the line through the slab's centre across the load. Each
    corner's friction force mu W / 4 lies across its radius r_i from (0, c), against the motion.
    Balance along x, alpha W = (mu W / 4) |sum_i (y_i - c) / r_i|, and of moments about (0, c),
    alpha W |e - c| = (mu W / 4) sum_i r_i, give c (the one root below 0 for e > 0) and alpha.
    alpha tends to mu as e -> 0 (c -> -infinity: pure sliding) and falls with e. The slab does
    not rock while b / h is large (overturning needs alpha = b / h about its far edge)."""
    from scipy.optimize import brentq

    if e <= 0.0:
        return mu
    a = b / 2.0
    y = np.array([a, a, -a, -a])

    def r(c):
        return np.hypot(a, y - c)

    c = brentq(lambda c: np.sum(r(c)) / abs(np.sum((y - c) / r(c))) - abs(c - e), -1e6 * b, -1e-12 * b)
    return float(mu / 4.0 * abs(np.sum((y - c) / r(c))))


def stack(n=3, dim=2, b=0.3, h=0.5, t=None, mu=0.6, name=None, **kw) -> dict:
    """n equal blocks stacked on a fixed base; block k has tag 'course-k', the top also 'top'."""
    t = b if t is None else t
    blocks = [base(dim, -b, 2 * b, -t, 2 * t)]
    for k in range(n):
        tags = [f"course-{k}"] + (["top"] if k == n - 1 else [])
        blocks.append(_place(dim, f"s{k}", 0.0, b, k * h, (k + 1) * h, 0.0, t, tags=tags))
    return scene(name or f"stack-{n}-{dim}d", dim, blocks, friction=mu, **kw)


def portal(dim=2, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, overhang=0.0, t=None, mu=0.6,
           name=None, **kw) -> dict:
    """Two single-block columns on a fixed base carrying a lintel (a trilithon).

    ``span`` is the clear opening between the columns; the lintel spans both
    columns fully (plus ``overhang`` at each end).
    """
    t = col_b if t is None else t
    x_l0, x_l1 = 0.0, col_b
    x_r0, x_r1 = col_b + span, 2 * col_b + span
    blocks = [base(dim, -col_b, x_r1 + col_b, -t, 2 * t),
              _place(dim, "col-left", x_l0, x_l1, 0.0, col_h, 0.0, t, tags=["column"]),
              _place(dim, "col-right", x_r0, x_r1, 0.0, col_h, 0.0, t, tags=["column"]),
              _place(dim, "lintel", x_l0 - overhang, x_r1 + overhang, col_h, col_h + lintel_h, 0.0, t,
                     tags=["lintel"])]
    return scene(name or f"portal-{dim}d", dim, blocks, friction=mu, **kw)


def side_by_side(dim=2, tall=(0.2, 1.0), squat=(0.5, 0.6), t=0.3, mu=0.5, name=None, **kw) -> dict:
    """A slender block "A" (b1 x h1) standing against a squat one "B" (b2 x h2) on a fixed base.

    Under a horizontal body force along +x the frictional collapse combines rocking
    and sliding: A rocks about its right toe, pivoting on B's top corner, and pushes
    B, which slides. With the friction at the A|B corner as favourable as
    equilibrium allows (|V| = mu H), the work and equilibrium equations give

        alpha = (h2 W_B mu + W_A b1 (1 + mu^2) / 2) / (W_A h1 (1 + mu^2) / 2 + h2 W_B),

    23/61 = 0.37705 for the defaults (mu = 0.5), below the associative LP's 7/17
    = 0.41176, whose dilatant sliding of B forbids that mechanism.
    """
    (b1, h1), (b2, h2) = tall, squat
    blocks = [base(dim, -b1, b1 + 2 * b2, -t, 2 * t),
              _place(dim, "A", 0.0, b1, 0.0, h1, 0.0, t, tags=["tall"]),
              _place(dim, "B", b1, b1 + b2, 0.0, h2, 0.0, t, tags=["squat"])]
    return scene(name or f"side-by-side-{dim}d", dim, blocks, friction=mu, **kw)


def side_by_side_alpha(tall=(0.2, 1.0), squat=(0.5, 0.6), mu=0.5, t=1.0) -> float:
    """The closed-form frictional collapse factor of :func:`side_by_side` (see there)."""
    (b1, h1), (b2, h2) = tall, squat
    WA, WB = b1 * h1 * t, b2 * h2 * t
    k = 1.0 + mu * mu
    return (h2 * WB * mu + WA * b1 * k / 2) / (WA * h1 * k / 2 + h2 * WB)


# ----------------------------------------------------------------------------
# Walls


def running_bond_wall(courses=3, per_course=3, dim=2, L=0.4, H=0.175, T=None, mu=0.65, name=None,
                      **kw) -> dict:
    """Running-bond wall: even courses hold ``per_course`` full blocks, odd courses a
    half block at each end and ``per_course - 1`` full blocks between.

    Blocks are L long, H high (and T thick in 3D; default T = L / 2). The wall
    stands on a fixed base; block ids are ``c{course}-{k}``; blocks carry the tag
    ``course-{course}`` and the end blocks also ``end``.
    """
    T = L / 2 if T is None else T
    blocks = [base(dim, -L, (per_course + 1) * L, -T, 2 * T)]
    for c in range(courses):
        z0, z1 = c * H, (c + 1) * H
        if c % 2 == 0:
            edges = [k * L for k in range(per_course + 1)]
        else:
            edges = [0.0] + [L / 2 + k * L for k in range(per_course)] + [per_course * L]
        nb = len(edges) - 1
        for k in range(nb):
            tags = [f"course-{c}"] + (["end"] if k in (0, nb - 1) else [])
            blocks.append(_place(dim, f"c{c}-{k}", edges[k], edges[k + 1], z0, z1, 0.0, T, tags=tags))
    return scene(name or f"wall-{courses}x{per_course}-{dim}d", dim, blocks, friction=mu, **kw)


def corner_walls(courses=4, len_a=4, len_b=3, L=0.4, H=0.2, mu=0.6, name=None, **kw) -> dict:
    """Two 3D walls meeting at a right-angle corner with interlocking courses.

    Wall A runs along +x, wall B along +y, both T = L/2 thick, with the corner
    square [0, T] x [0, T]. In even courses wall A's first block runs through
    the corner, in odd courses wall B's does (the usual alternate bond).
    ``len_a``, ``len_b``: wall lengths in whole blocks beyond the corner square.
    """
    T = L / 2
    XA = T + len_a * L  # outer length of wall A
    YB = T + len_b * L
    blocks = [base(3, -L, XA + L, -L, YB + L)]
    for c in range(courses):
        z0, z1 = c * H, (c + 1) * H
        a_start, b_start = (0.0, T) if c % 2 == 0 else (T, 0.0)
        # Wall A along x over [a_start, XA], y in [0, T]
        xs = _bond_edges(a_start, XA, L)
        for k in range(len(xs) - 1):
            blocks.append(box_block(f"A{c}-{k}", [(xs[k] + xs[k + 1]) / 2, T / 2, (z0 + z1) / 2],
                                    [xs[k + 1] - xs[k], T, H], tags=["wall-a", f"course-{c}"]))
        ys = _bond_edges(b_start, YB, L)
        for k in range(len(ys) - 1):
            blocks.append(box_block(f"B{c}-{k}", [T / 2, (ys[k] + ys[k + 1]) / 2, (z0 + z1) / 2],
                                    [T, ys[k + 1] - ys[k], H], tags=["wall-b", f"course-{c}"]))
    return scene(name or f"corner-walls-{courses}", 3, blocks, friction=mu, **kw)


def _bond_edges(start, end, L):
    """Joint positions from ``start`` to ``end`` with blocks of length L; the last
    block takes what is left (merged into its neighbour if under L/4)."""
    edges = [start]
    x = start + L
    while x < end - 1e-9 * L:
        edges.append(x)
        x += L
    if end - edges[-1] < 0.25 * L and len(edges) > 1:  # avoid slivers: merge into the previous block
        edges.pop()
    edges.append(end)
    return edges


# ----------------------------------------------------------------------------
# Arches


def arch(n=9, R=1.0, t=0.15, span_deg=180.0, dim=2, depth=None, support_h=0.3, mu=0.6, name=None,
         **kw) -> dict:
    """Circular arch of ``n`` equal voussoirs between two fixed supports.

    ``R`` is the radius of the centre line, ``t`` the ring thickness,
    ``span_deg`` the angle the arch subtends (180 = semicircular, less =
    segmental). Springing joints are radial; each support's top is its springing
    joint. In 3D the arch is extruded over ``depth`` (default t) along y.
    Voussoirs are ``v0`` (right) to ``v{n-1}`` (left), tagged 'voussoir'.
    """
    ri, re = R - t / 2, R + t / 2
    phi0 = math.radians(90.0 - span_deg / 2)
    phis = np.linspace(phi0, math.pi - phi0, n + 1)
    depth = t if depth is None else depth
    blocks = []
    polys = []
    for k in range(n):
        a0, a1 = phis[k], phis[k + 1]
        polys.append(("v%d" % k, [[ri * math.cos(a0), ri * math.sin(a0)], [re * math.cos(a0), re * math.sin(a0)],
                                  [re * math.cos(a1), re * math.sin(a1)], [ri * math.cos(a1), ri * math.sin(a1)]],
                      ["voussoir"]))
    # Supports: below the springing joints, flat bottom at y_b.
    y_b = min(ri * math.sin(phi0), re * math.sin(phi0)) - support_h
    pi_, pe_ = (ri * math.cos(phi0), ri * math.sin(phi0)), (re * math.cos(phi0), re * math.sin(phi0))
    right = [pi_, pe_, (pe_[0], y_b), (pi_[0], y_b)]
    left = [(-x, y) for x, y in right]
    support = [("support-right", right), ("support-left", left)]
    for sid, pts in support:
        blocks.append(_extrude(sid, pts, dim, depth, fixed=True))
    for vid, pts, tags in polys:
        blocks.append(_extrude(vid, pts, dim, depth, tags=tags))
    kind = "semicircular" if abs(span_deg - 180) < 1e-9 else "segmental"
    return scene(name or f"arch-{kind}-{n}-{dim}d", dim, blocks, friction=mu, **kw)


def _extrude(bid, pts2, dim, depth, fixed=False, **kw):
    """A 2D outline as a 2D block, or extruded along y over [0, depth] in 3D (x, z from the outline)."""
    pts2 = np.asarray(pts2, dtype=float)
    if dim == 2:
        return vertex_block(bid, pts2, fixed=fixed, **kw)
    v = [[x, y, z] for y in (0.0, depth) for x, z in pts2]
    return vertex_block(bid, v, fixed=fixed, **kw)
