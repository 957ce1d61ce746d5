"""The structures of Baggio & Trovalusci's paper, rebuilt as scenes.

Source: C. Baggio, P. Trovalusci, "Collapse behaviour of three-dimensional
brick-block systems using non-linear programming", Structural Engineering and
Mechanics 10(2) (2000) 181-195 (text in ``../shared/papers/``), Figs. 1-7.

The paper's text gives the block and joint counts, the loads and a few collapse
factors, not the dimensions: every geometry here is a reconstruction that meets
the counts and the description (stated per builder), not a copy of the drawing.
So a published alpha is shown beside ours as a published value, with the
reason for any difference, not used as a pass/fail reference (except where the
paper's statement is geometry-free, as in Fig. 1).

Axes as in :mod:`scenes.builders`: 2D x horizontal, y up; 3D z up, the live
load a horizontal body force along +x unless stated.
"""
from __future__ import annotations

import math

import numpy as np

from limit.geom.geometry import polygon_area_centroid

from . import builders as B

PAPER = ("Baggio & Trovalusci, Collapse behaviour of three-dimensional brick-block systems "
         "using non-linear programming, Struct. Eng. Mech. 10(2), 2000")


def fig1_block(mu=0.5, b=1.0, h=0.5, **kw) -> dict:
    """Fig. 1: one squat block (b/h = 2 > mu) on a fixed plane under its weight and a
    horizontal body force: it slides at alpha = mu, with friction (Fig. 1a) and with
    dilatancy (Fig. 1b: the block climbs a plane inclined at the friction angle, and the
    dead load's work makes up for the dilatancy): the two steps agree."""
    return B.single_block(dim=2, b=b, h=h, mu=mu, **kw)


# ----------------------------------------------------------------------------
# Fig. 5: trilithic structure, 17 blocks, 26 joints


def fig5_trilithic(col_b=0.3, col_h=3.5, bay=1.6, row_gap=2.0, arch_h=0.4, beam_h=0.3, beam_b=0.4, mu=0.6,
                   **kw) -> dict:
    """Fig. 5: two rows (along x) of three columns, each column two drums (col_b square,
    col_h / 2 high); per row two architraves (col_b wide, arch_h high), the first from
    the outer face of the first column to the middle of the second, the other from there
    to the outer face of the third, so they meet end to end over the middle column;
    one transversal beam (beam_b wide, beam_h high) across the rows over the middle
    columns, resting on the four architrave ends there.

    Counts: 12 drums + 4 architraves + 1 beam = 17 blocks; joints: 6 column bases,
    6 drum-drum, 8 architrave-column, 2 architrave-architrave, 4 beam-architrave = 26.

    The live load is a body force along x (the rows' direction): every column rocks
    about its toe with the architraves translating on top (the sway of a portal), at
    alpha = col_b / col_h whatever the weights. The paper reports alpha = 0.086 and
    draws that mechanism (equal rotations of all piers about y) but gives no
    dimensions: the column slenderness col_b / col_h = 0.3 / 3.5 = 0.0857 is chosen to
    match, so our value checks the mechanism and the two-step procedure, not the
    paper's geometry.
    """
    blocks = [B.box_block("base", [bay, row_gap / 2, -0.1], [2 * bay + 4 * col_b, row_gap + 4 * col_b, 0.2],
                          fixed=True)]
    hd = col_h / 2
    for r, y in enumerate((0.0, row_gap)):
        for c in range(3):
            x = c * bay
            for k in range(2):
                blocks.append(B.box_block(f"col{r}{c}-{k}", [x, y, hd * (k + 0.5)], [col_b, col_b, hd],
                                          tags=["column"]))
        z = col_h + arch_h / 2
        x0, x1, x2 = -col_b / 2, bay, 2 * bay + col_b / 2
        blocks.append(B.box_block(f"arch{r}-0", [(x0 + x1) / 2, y, z], [x1 - x0, col_b, arch_h], tags=["architrave"]))
        blocks.append(B.box_block(f"arch{r}-1", [(x1 + x2) / 2, y, z], [x2 - x1, col_b, arch_h], tags=["architrave"]))
    y0, y1 = -col_b / 2, row_gap + col_b / 2
    blocks.append(B.box_block("beam", [bay, (y0 + y1) / 2, col_h + arch_h + beam_h / 2], [beam_b, y1 - y0, beam_h],
                              tags=["beam"]))
    return B.scene(kw.pop("name", "paper-fig5-trilithic-3d"), 3, blocks, friction=mu, **kw)


# ----------------------------------------------------------------------------
# Fig. 6: two intersecting walls, 25 blocks, 61 joints


def fig6_intersecting_walls(mu=0.6, **kw) -> dict:
    """Fig. 6: a wall loaded out of its plane (along x; the wall runs along y) held
    by its interlocking with a short perpendicular panel (a pilaster, along x): five
    courses in alternate bond at the corner, :func:`scenes.builders.corner_walls`
    with one block of panel and three of wall beyond the corner square.
    Counts: 25 blocks, 61 joints, as in the paper. Blocks 0.4 x 0.2 x 0.2 m.
    The paper gives no collapse factor in its text."""
    return B.corner_walls(courses=5, len_a=1, len_b=3, L=0.4, H=0.2, mu=mu,
                          name=kw.pop("name", "paper-fig6-intersecting-walls-3d"), **kw)


# ----------------------------------------------------------------------------
# Fig. 7: fountain basin, 48 blocks, 96 joints, halved by symmetry


def _polygon_radius(theta, apothem, n_sides):
    """Distance from the centre to a regular n-gon (corners at angles 2 pi k / n) along theta."""
    step = 2 * math.pi / n_sides
    rel = (theta % step) - step / 2
    return apothem / math.cos(rel)


def fig7_fountain(half=True, n_sides=12, apothem=2.5, t=0.3, pil_deg=4.0, h_low=0.6, h_top=0.25, mu=0.6,
                  **kw) -> dict:
    """Fig. 7: the upper basin of the Fontana Maggiore (Perugia) as a 12-sided ring
    wall: at each corner a pilaster, between two corners a marble panel (lower course,
    h_low high), each with its entablature piece above (upper course, h_top high), all
    joints radial and aligned: 12 x 2 x 2 = 48 blocks and 24 head + 24 bed joints per
    course = 96 joints (a bed joint of the lower course is on the fixed plinth).
    ``apothem`` is the outer polygon's, the ring t thick; a pilaster spans pil_deg
    either side of its corner.

    ``half``: the paper used the symmetry of the load (x) about the plane y = 0 to
    halve the problem. The half model keeps the blocks with y >= 0; the two pilasters
    and entablature pieces on the plane (at 0 and 180 degrees) are cut in half and have
    the symmetric motion's constraints: no velocity across the plane, no rotation about
    x or z (``"blocked": ["y", "rx", "rz"]``). 26 blocks, 50 joints; with the paper's
    ten faces per joint about 500 kinematic unknowns, as the paper says.
    """
    ai, ao = apothem - t, apothem
    step = 360.0 / n_sides
    cuts = []  # (a0, a1, kind, corner index) in degrees, going round from 0
    for k in range(n_sides):
        c = k * step
        cuts.append((c - pil_deg, c + pil_deg, "pilaster", k))
        cuts.append((c + pil_deg, c + step - pil_deg, "panel", k))
    blocks = []
    plinth = [[r * math.cos(a), r * math.sin(a), z] for z in (-0.3, 0.0)
              for a in np.radians(np.arange(n_sides) * step)
              for r in [(ao + 0.3) / math.cos(math.radians(step / 2))]]
    if half:
        plinth = [[x, max(y, 0.0), z] for x, y, z in plinth]
    blocks.append(B.vertex_block("plinth", plinth, fixed=True))
    for course, (z0, z1) in enumerate(((0.0, h_low), (h_low, h_low + h_top))):
        for a0, a1, kind, k in cuts:
            blocked = None
            if half:
                if a1 <= 0.0 + 1e-9 or a0 >= 180.0 - 1e-9:
                    continue
                if a0 < 0.0 < a1 or a0 < 180.0 < a1:
                    a0, a1 = max(a0, 0.0), min(a1, 180.0)
                    blocked = ["y", "rx", "rz"]
            corner = k * step
            inner = [a0, a1]
            outer = [a0] + ([corner] if a0 < corner < a1 else []) + [a1]
            pts = [(_polygon_radius(math.radians(a), ai, n_sides), a) for a in inner] + \
                  [(_polygon_radius(math.radians(a), ao, n_sides), a) for a in outer]
            verts = [[r * math.cos(math.radians(a)), r * math.sin(math.radians(a)), z] for r, a in pts
                     for z in (z0, z1)]
            name = f"{kind}-{k}" if course == 0 else f"entablature-{kind}-{k}"
            tags = [kind if course == 0 else "entablature", f"course-{course}"]
            blk = B.vertex_block(name, verts, tags=tags)
            if blocked:
                blk["blocked"] = blocked
            blocks.append(blk)
    # the mirror plane leaves exact zeros at y = 0: keep them exact
    for blk in blocks:
        for v in blk["vertices"]:
            if abs(v[1]) < 1e-12:
                v[1] = 0.0
    default = "paper-fig7-fountain-half-3d" if half else "paper-fig7-fountain-full-3d"
    return B.scene(kw.pop("name", default), 3, blocks, friction=mu, **kw)


# ----------------------------------------------------------------------------
# Fig. 2: double-level arches on piers, 55 units, 74 interfaces


def _ring(prefix, n, R, t, cx, cy, tags):
    """n voussoirs of a semicircular ring (centre line radius R, thickness t, centre
    (cx, cy)), horizontal springing joints at y = cy, numbered from the right."""
    ri, re = R - t / 2, R + t / 2
    phis = np.linspace(0.0, math.pi, n + 1)
    out = []
    for k in range(n):
        a0, a1 = phis[k], phis[k + 1]
        pts = [[cx + r * math.cos(a), cy + r * math.sin(a)] for r, a in ((ri, a0), (re, a0), (re, a1), (ri, a1))]
        out.append(B.vertex_block(f"{prefix}{k}", pts, tags=tags))
    return out


def fig2_double_arch(texture="a", R1=1.0, t1=0.2, w=0.34, c1=8, h1=0.2, c2=3, h2=0.3, n1=7, n2=9, mu=0.6,
                     **kw) -> dict:
    """Fig. 2: two semicircular arches one above the other on two stone piers, a
    spacer stone between their crowns (the "I Sassi", Matera, double-level arches).

    Lower arch: n1 voussoirs, centre-line radius R1, thickness t1, springing at
    Hs1 = c1 h1. Each pier is t1 + w wide below Hs1 (c1 courses of h1) and w wide
    above (c2 courses of h2, the outer part, up to Hs2); the upper arch (n2
    voussoirs, thickness w, radius R1 + t1/2 + w/2) springs from there, concentric
    with the lower one but Hs2 - Hs1 higher.

    Textures of the lower piers:

    * ``"a"`` two stones per course (t1 and w wide) with one continuous vertical
      joint: the inner stack under the lower arch's springing stands on its own.
      Counts: 2 x (16 + 3) pier stones + 7 + 9 voussoirs + 1 spacer = 55 units,
      2 x (8 head + 16 bed + 3 bed) + 8 + 10 arch joints + 2 spacer joints = 74
      interfaces: the paper's numbers for Fig. 2a.
    * ``"b"`` the same stones bonded: the joint alternates between t1 and t1 + w/2
      from the inner face, so the courses tie the inner and outer parts together.

    Loads: the paper's caption says "the dead self weight and a live extra-charge";
    its text, dead loads on the pier stones and live vertical loads on the voussoirs
    proportional to their weight. Taken literally the second is ill-posed for the
    frictional step: with the arches loaded by the live load alone, alpha = 0 (weightless
    voussoirs sliding apart at zero force) solves the non-associative problem. So here
    the dead load is the self weight of every stone and the live load an extra
    vertical charge on the arch stones (voussoirs and spacer) equal to alpha times
    their weight: the paper's alpha (arch load / arch weight) is 1 + ours. The
    paper: texture (a) cannot carry the arches' full weight (here: collapse under
    the dead load alone, "infeasible"), texture (b) carries 15 % more (1 + alpha =
    1.15). The text gives no dimensions: these are ours, the pier width w = 0.34 m
    picked (from 0.30-0.45) so that (b) lands near the paper's 1.15 while (a) falls.
    """
    Hs1, Hs2 = c1 * h1, c1 * h1 + c2 * h2
    x_in, x_mid, x_out = R1 - t1 / 2, R1 + t1 / 2, R1 + t1 / 2 + w
    blocks = [B.box_block("ground", [0.0, -0.15], [2 * x_out + 1.0, 0.3], fixed=True)]
    for side, sgn in (("r", 1.0), ("l", -1.0)):
        def stone(bid, xa, xb, y0, y1):
            lo, hi = sorted((sgn * xa, sgn * xb))
            return B.box_block(bid, [(lo + hi) / 2, (y0 + y1) / 2], [hi - lo, y1 - y0], tags=["pier"])

        for c in range(c1):
            split = x_mid if (texture == "a" or c % 2 == 0) else x_mid + w / 2
            blocks.append(stone(f"p{side}{c}-0", x_in, split, c * h1, (c + 1) * h1))
            blocks.append(stone(f"p{side}{c}-1", split, x_out, c * h1, (c + 1) * h1))
        for c in range(c2):
            blocks.append(stone(f"p{side}{c1 + c}", x_mid, x_out, Hs1 + c * h2, Hs1 + (c + 1) * h2))
    blocks += _ring("a", n1, R1, t1, 0.0, Hs1, ["voussoir", "lower-arch", "arches"])
    R2 = R1 + t1 / 2 + w / 2
    blocks += _ring("b", n2, R2, w, 0.0, Hs2, ["voussoir", "upper-arch", "arches"])
    y_lo = Hs1 + (R1 + t1 / 2) * math.cos(math.pi / (2 * n1))   # lower keystone's extrados chord
    y_hi = Hs2 + (R2 - w / 2) * math.cos(math.pi / (2 * n2))     # upper keystone's intrados chord
    half = 0.4 * min((R1 + t1 / 2) * math.sin(math.pi / (2 * n1)), (R2 - w / 2) * math.sin(math.pi / (2 * n2)))
    blocks.append(B.box_block("spacer", [0.0, (y_lo + y_hi) / 2], [2 * half, y_hi - y_lo], tags=["spacer", "arches"]))
    live = [{"type": "body_force", "direction": [0.0, -1.0], "blocks": {"tags": ["arches"]}}]
    return B.scene(kw.pop("name", f"paper-fig2{texture}-double-arch-2d"), 2, blocks, friction=mu, live=live, **kw)


# ----------------------------------------------------------------------------
# Fig. 4: opus africanum, 57 stones, 138 joints


def _bond(x0, x1, ls, offset):
    """Joint positions filling [x0, x1] with stones ls long, the first one shortened
    by ``offset``; pieces under ls / 3 are merged into their neighbour."""
    edges = [x0]
    x = x0 + (ls - offset if offset > 0 else ls)
    while x < x1 - 1e-9:
        edges.append(x)
        x += ls
    edges.append(x1)
    if len(edges) > 2 and edges[1] - edges[0] < ls / 3:
        edges.pop(1)
    if len(edges) > 2 and edges[-1] - edges[-2] < ls / 3:
        edges.pop(-2)
    return edges


def fig4_opus_africanum(n_piers=3, panel=1.8, hc=0.3, v_courses=2,
                        pattern=(("v", "v", "h"), ("v", "v", "h"), ("h", "v", "h", "h")), wv=0.3, wh=0.6,
                        ls=0.4, offset=(0.0, 0.5), mu=0.6, **kw) -> dict:
    """Fig. 4: 'opus africanum': piers of large stones, alternately upright (wv wide,
    v_courses x hc high) and lying (wh wide, hc high), framing panels of small
    stones in courses (hc high, stones about ls long, cut to fit against the piers;
    alternate courses shifted by ``offset`` x ls per panel: 0 stacked, 0.5 running
    bond). ``pattern``: one sequence per pier, bottom up, "v" upright, "h" lying.
    Pier centres ``panel`` + wv apart (one value per panel or one for all); the wall
    stands on a fixed ground and carries its self weight (dead) and a horizontal
    body force (live). The defaults (an irregular frame: the piers differ, the left
    panel is stacked and the right one bonded) give 10 pier stones and 47 small ones
    = 57 stones and 138 joints, the paper's counts, found by a search over these
    knobs; the dimensions are ours. The paper reports alpha = 0.106 from an
    arbitrary start (a poor local solution) and better values from the LP start
    (figure values, not in its text)."""
    panels = list(panel) if isinstance(panel, (list, tuple)) else [panel] * (n_piers - 1)
    offsets = list(offset) if isinstance(offset, (list, tuple)) else [offset] * (n_piers - 1)
    xs = np.concatenate([[0.0], np.cumsum([p + wv for p in panels])])  # pier centres
    pats = [pattern] * n_piers if isinstance(pattern[0], str) else list(pattern)
    n_courses = round(sum(v_courses if p == "v" else 1 for p in pats[0]))
    blocks = [B.box_block("ground", [xs[-1] / 2, -0.15], [xs[-1] + 2 * wh + 1.0, 0.3], fixed=True)]
    # pier stones and the half widths of the piers per course
    half = np.zeros((n_piers, n_courses))
    for k in range(n_piers):
        xc = xs[k]
        y = 0.0
        heights = [v_courses * hc if p == "v" else hc for p in pats[k]]
        if round(sum(heights) / hc) != n_courses:
            raise ValueError("every pier pattern must be as high as the first")
        for j, (p, h) in enumerate(zip(pats[k], heights)):
            w = wv if p == "v" else wh
            blocks.append(B.box_block(f"pier{k}-{j}", [xc, y + h / 2], [w, h], tags=["pier", "upright" if p == "v"
                                                                                      else "lying"]))
            c0 = round(y / hc)
            half[k, c0:c0 + round(h / hc)] = w / 2
            y += h
    for c in range(n_courses):
        for k in range(n_piers - 1):
            x0, x1 = xs[k] + half[k, c], xs[k + 1] - half[k + 1, c]
            edges = _bond(x0, x1, ls, offsets[k] * ls if c % 2 else 0.0)
            for i in range(len(edges) - 1):
                blocks.append(B.box_block(f"s{k}-{c}-{i}", [(edges[i] + edges[i + 1]) / 2, (c + 0.5) * hc],
                                          [edges[i + 1] - edges[i], hc], tags=["small", f"course-{c}"]))
    return B.scene(kw.pop("name", "paper-fig4-opus-africanum-2d"), 2, blocks, friction=mu, **kw)


# ----------------------------------------------------------------------------
# Fig. 3: polygonal-stone walls ('opus poligonale')


def _bounded_voronoi(pts, W, H):
    """Voronoi cells of ``pts`` clipped to the box [0, W] x [0, H] (each point mirrored
    across the four sides, so the box's sides are cell edges): a list of (k, 2) arrays."""
    from scipy.spatial import Voronoi

    mirrored = [pts, pts * [-1, 1], pts * [-1, 1] + [2 * W, 0], pts * [1, -1], pts * [1, -1] + [0, 2 * H]]
    vor = Voronoi(np.vstack(mirrored))
    cells = []
    for i in range(len(pts)):
        region = vor.regions[vor.point_region[i]]
        v = vor.vertices[region]
        v[:, 0] = np.where(np.abs(v[:, 0]) < 1e-9 * W, 0.0, np.where(np.abs(v[:, 0] - W) < 1e-9 * W, W, v[:, 0]))
        v[:, 1] = np.where(np.abs(v[:, 1]) < 1e-9 * H, 0.0, np.where(np.abs(v[:, 1] - H) < 1e-9 * H, H, v[:, 1]))
        cells.append(v)
    return cells


def fig3_opus_poligonale(n_stones=40, W=1.6, H=2.0, seed=1, lloyd=20, aspect=1.0, mu=0.6, **kw) -> dict:
    """Fig. 3: a wall of polygonal stones, W wide and H high on a fixed ground: the
    Voronoi cells of ``n_stones`` random points (seeded), made rounder by ``lloyd``
    Lloyd iterations, so each stone is a convex polygon with several neighbours at
    scattered orientations. Self weight (dead) and a horizontal body force (live) as
    in the paper, whose three walls (three Italian historic centres) behaved almost
    as monoliths: the LP alpha stays near, and never above, the monolith's
    overturning W / H. No alpha is given in the paper's text. ``aspect`` > 1 makes
    the stones that much wider than high (the cells are built in a box squeezed
    along x by ``aspect`` and stretched back: an affine map keeps them convex)."""
    rng = np.random.default_rng(seed)
    Ws = W / aspect
    pts = rng.uniform([0, 0], [Ws, H], size=(n_stones, 2))
    for _ in range(lloyd):
        cells = _bounded_voronoi(pts, Ws, H)
        pts = np.array([_centroid2(c) for c in cells])
    cells = [c * [aspect, 1.0] for c in _bounded_voronoi(pts, Ws, H)]
    blocks = [B.box_block("ground", [W / 2, -0.15], [W + 1.0, 0.3], fixed=True)]
    for k, c in enumerate(cells):
        blocks.append(B.vertex_block(f"st{k}", _ccw(c), tags=["stone"]))
    return B.scene(kw.pop("name", f"paper-fig3-opus-poligonale-{n_stones}-2d"), 2, blocks, friction=mu, **kw)


def _ccw(v):
    c = v.mean(axis=0)
    return v[np.argsort(np.arctan2(v[:, 1] - c[1], v[:, 0] - c[0]))]


def _centroid2(v):
    return polygon_area_centroid(_ccw(v))[1]
