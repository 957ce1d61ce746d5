"""Walls in running, English or Flemish bond, 2D (the elevation) or 3D, with openings spanned by
a lintel or a flat arch.

2D: x along the wall, y up (the scene's ``thickness`` is the wall's). 3D: x along the wall, y
across it (the wall occupies y in [0, T]), z up. The wall stands on a fixed base whose top is at
height 0. Lengths in metres.
"""
from __future__ import annotations

import math

from limit.errors import SceneError

from .. import builders as B
from . import bonds
from ._common import choice, count, dimension, finish, outline_block, positive

HEADS = ("lintel", "arch", "round")


def wall(length=2.4, height=1.6, bond="running", dim=2, unit=(0.4, 0.2, 0.2), thickness=None, openings=(),
         lintel_bearing=None, arch_courses=2, arch_voussoirs=5, arch_skew_deg=20.0, mu=0.6, density=2000.0,
         name=None) -> dict:
    """A wall of stretchers and headers, with openings; returns a ``blockscene/1`` dict.

    length: of the wall along x (m).
    height: of the wall (m), a whole number of courses.
    bond: 'running', 'english' or 'flemish' (scenes.generators.bonds).
    dim: 2 (the elevation; the scene's thickness is the wall's) or 3.
    unit: (L, W, H), the stretcher's length, its depth (= a header's length) and the course height (m).
    thickness: the wall's (m); default W for running bond, L for English and Flemish bond, whose
        stretcher courses are two wythes of depth thickness/2 (3D) and whose headers run through.
    openings: list of {"x", "width", "sill", "height", "head"}: left edge, clear width, sill height
        and clear height (m; sill and sill + height on course lines), head 'lintel' (default), 'arch'
        (a flat arch) or 'round' (a semicircular arch springing at sill + height; see round_head).
    lintel_bearing: how far a lintel (one course high) rests on the wall each side (m; default L/2).
    arch_courses: a flat arch's height in courses.
    arch_voussoirs: a flat arch's voussoirs (odd); its joints radiate from one point below the opening.
    arch_skew_deg: the inclination of a flat arch's skewbacks from the vertical (degrees).
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: 'c{course}-{k}' (and 'c{course}-{k}f'/'...b', the front and back stretchers of a
    two-wythe course in 3D), tagged 'course-{course}' and 'stretcher' or 'header'; 'lintel-{i}'
    tagged 'lintel'; 'arch-{i}-{k}' (flat or round arch) tagged 'arch' and 'voussoir' (the ends also
    'springing', the middle one 'key'); all of opening i's head also 'opening-{i}'. Fixed base 'base'.
    Loads: self weight (dead), a body force of 1 g along +x (live).
    """
    params = dict(length=length, height=height, bond=bond, dim=dim, unit=tuple(unit), thickness=thickness,
                  openings=[dict(o) for o in openings], lintel_bearing=lintel_bearing, arch_courses=arch_courses,
                  arch_voussoirs=arch_voussoirs, arch_skew_deg=arch_skew_deg, mu=mu, density=density)
    choice("bond", bond, bonds.BONDS)
    dim = dimension(dim)
    if len(unit) != 3:
        raise SceneError(f"unit: expected (L, W, H) in m, got {unit!r}")
    L, W, H = (positive(f"unit[{k}]", u) for k, u in enumerate(unit))
    Lw, Hw = positive("length", length), positive("height", height)
    nc = _courses("height", Hw, H)
    T = (W if bond == "running" else L) if thickness is None else positive("thickness", thickness)
    bearing = L / 2 if lintel_bearing is None else positive("lintel_bearing", lintel_bearing, allow_zero=True)
    na = count("arch_courses", arch_courses)
    nv = count("arch_voussoirs", arch_voussoirs, 1)
    if nv % 2 == 0:
        raise SceneError(f"arch_voussoirs: must be odd (a key in the middle), got {nv}")
    skew = math.tan(math.radians(positive("arch_skew_deg", arch_skew_deg, allow_zero=True)))
    if skew * na * H > 10 * Lw:
        raise SceneError(f"arch_skew_deg: too large, got {arch_skew_deg!r}")

    # Per course, the occupied intervals: (left bottom, left top, right bottom, right top).
    occupied = {c: [] for c in range(nc)}
    heads = []  # blocks of the openings' heads
    for i, o in enumerate(openings):
        where = f"openings[{i}]"
        unknown = set(o) - {"x", "width", "sill", "height", "head"}
        if unknown:
            raise SceneError(f"{where}: unknown key {sorted(unknown)[0]!r} (x, width, sill, height, head)")
        try:
            x0 = float(o["x"])
            w = positive(f"{where}.width", o["width"])
            sill = positive(f"{where}.sill", o.get("sill", 0.0), allow_zero=True)
            h = positive(f"{where}.height", o["height"])
        except KeyError as exc:
            raise SceneError(f"{where}: needs the key {exc.args[0]!r}") from None
        head = choice(f"{where}.head", o.get("head", "lintel"), HEADS)
        c0, c1 = _courses(f"{where}.sill", sill, H, zero=True), _courses(f"{where}.height", sill + h, H)
        x1 = x0 + w
        if head == "round":
            ang, re = round_head(w, H)
            band = len(ang) - 1
        else:
            band = 1 if head == "lintel" else na
        if c1 + band > nc:
            raise SceneError(f"{where}: its {head} ({band} course(s) above the opening) does not fit under the "
                             f"wall's top: raise the height or lower the opening")
        if head == "lintel":
            l0, l1 = x0 - bearing, x1 + bearing
            if l0 < -1e-9 or l1 > Lw + 1e-9:
                raise SceneError(f"{where}: the lintel with its bearing ({l0:g} to {l1:g} m) leaves the wall "
                                 f"(0 to {Lw:g} m)")
            l0, l1 = max(l0, 0.0), min(l1, Lw)
            for c in range(c0, c1):
                occupied[c].append((x0, x0, x1, x1, i))
            occupied[c1].append((l0, l0, l1, l1, i))
            heads.append(outline_block(f"lintel-{i}", [[l0, c1 * H], [l1, c1 * H], [l1, (c1 + 1) * H],
                                                        [l0, (c1 + 1) * H]], dim, 0.0, T,
                                       tags=["lintel", f"opening-{i}"]))
            continue
        if x0 < -1e-9 or x1 > Lw + 1e-9:
            raise SceneError(f"{where}: the opening ({x0:g} to {x1:g} m) leaves the wall (0 to {Lw:g} m)")
        zh, ha = c1 * H, na * H
        xc = (x0 + x1) / 2
        for c in range(c0, c1):
            occupied[c].append((x0, x0, x1, x1, i))
        if head == "round":
            if xc - re < -1e-9 or xc + re > Lw + 1e-9:
                raise SceneError(f"{where}: the round arch's extrados ({xc - re:.4g} to {xc + re:.4g} m) leaves "
                                 f"the wall (0 to {Lw:g} m)")
            dx = [re * math.cos(a) for a in ang]
            for k in range(band):
                occupied[c1 + k].append((xc - dx[k], xc - dx[k + 1], xc + dx[k], xc + dx[k + 1], i))
            full = ang + [math.pi - a for a in reversed(ang)]  # joint angles, right springing to left
            nvr = len(full) - 1
            for k in range(nvr):
                a0, a1 = full[k], full[k + 1]
                pts = [[xc + r * math.cos(a), zh + r * math.sin(a)] for r, a in
                       ((w / 2, a0), (re, a0), (re, a1), (w / 2, a1))]
                tags = ["arch", "voussoir", f"opening-{i}"] + (["springing"] if k in (0, nvr - 1) else []) + \
                    (["key"] if k == nvr // 2 else [])
                heads.append(outline_block(f"arch-{i}-{k}", pts, dim, 0.0, T, tags=tags))
            continue
        if x0 - skew * ha < -1e-9 or x1 + skew * ha > Lw + 1e-9:
            raise SceneError(f"{where}: the flat arch's skewbacks leave the wall; move the opening inwards "
                             f"or lower arch_skew_deg")
        for c in range(c1, c1 + na):
            d0, d1 = (c - c1) * H * skew, (c + 1 - c1) * H * skew
            occupied[c].append((x0 - d0, x0 - d1, x1 + d0, x1 + d1, i))
        # joints radiate from (xc, zh - depth): the skewbacks pass through the opening's corners
        for k in range(nv):
            xs = [x0 + (k + e) * w / nv for e in (0, 1)]
            tops = [xc + (xk - xc) * (1 + ha * skew / (w / 2)) for xk in xs]
            tags = ["arch", "voussoir", f"opening-{i}"] + (["springing"] if k in (0, nv - 1) else []) + \
                (["key"] if k == nv // 2 else [])
            heads.append(outline_block(f"arch-{i}-{k}", [[xs[0], zh], [xs[1], zh], [tops[1], zh + ha],
                                                          [tops[0], zh + ha]], dim, 0.0, T, tags=tags))
    blocks = [B.base(dim, -L, Lw + L, -T, 2 * T)]
    for c in range(nc):
        z0, z1 = c * H, (c + 1) * H
        occ = sorted(occupied[c])
        for (p, q) in zip(occ, occ[1:]):
            if min(q[0], q[1]) < max(p[2], p[3]) - 1e-9:
                raise SceneError(f"openings[{q[4]}]: overlaps openings[{p[4]}] (or its lintel or arch) "
                                 f"in course {c}")
        ends = [(0.0, 0.0)] + [e for o in occ for e in ((o[0], o[1]), (o[2], o[3]))] + [(Lw, Lw)]
        k = 0
        for j in range(0, len(ends), 2):
            (a, a_t), (b, b_t) = ends[j], ends[j + 1]
            width = min(b, b_t) - max(a, a_t)
            if width <= 1e-9:
                continue
            if width < bonds.min_piece(L, W):
                raise SceneError(f"openings: course {c} keeps a piece only {width:.4g} m wide between {a:g} and "
                                 f"{b:g} m (less than {bonds.min_piece(L, W):.4g} m); move or widen the openings")
            pieces = bonds.cut(bond, c, a, b, L, W, a_t, b_t)
            for m, (x0, x1, kind) in enumerate(pieces):
                x0t = a_t if m == 0 else x0
                x1t = b_t if m == len(pieces) - 1 else x1
                pts = [[x0, z0], [x1, z0], [x1t, z1], [x0t, z1]]
                tags = [f"course-{c}", "stretcher" if kind == "S" else "header"]
                if dim == 3 and bond != "running" and kind == "S":
                    blocks.append(outline_block(f"c{c}-{k}f", pts, 3, 0.0, T / 2, tags=tags + ["front"]))
                    blocks.append(outline_block(f"c{c}-{k}b", pts, 3, T / 2, T, tags=tags + ["back"]))
                else:
                    blocks.append(outline_block(f"c{c}-{k}", pts, dim, 0.0, T, tags=tags))
                k += 1
    blocks += heads
    extra = {"thickness": T} if dim == 2 else {}
    sc = B.scene(name or f"wall-{bond}-{dim}d", dim, blocks, friction=float(mu), density=float(density),
                 sliding_faces=None, **extra)
    return finish(sc, f"Wall in {bond} bond" + (f" with {len(openings)} opening(s)" if openings else ""), params)


def round_head(width, H, key_half_deg=15.0):
    """A round-headed opening's ring: the joint angles from the right springing to the key's
    joint, and the extrados radius (m). The intrados is the semicircle of radius width/2; the
    extrados vertices lie on course lines (at heights k H above the springing, k = 0..K), so each
    course beside the ring meets it along one chord, and the key's flat top, at K H, carries the
    course above. K = round(width/2/H + 1) and the extrados radius K H / cos(key_half_deg) make
    the ring about one course thick and the key span 2 key_half_deg degrees."""
    K = max(1, round(width / 2 / H + 1))
    re = K * H / math.cos(math.radians(key_half_deg))
    if re <= width / 2 + 0.25 * H:
        K += 1
        re = K * H / math.cos(math.radians(key_half_deg))
    return [math.asin(k * H / re) for k in range(K + 1)], re


def _courses(name, z, H, zero=False):
    """z / H as a whole number of courses, or a SceneError naming ``name``."""
    n = round(z / H)
    if abs(n * H - z) > 1e-9 * max(1.0, z) or (n < 1 and not zero):
        raise SceneError(f"{name}: {z:g} m is not a whole number of courses of {H:g} m")
    return n
