"""Masonry bonds: where the head joints of a course fall, and which units (stretcher 'S' or header
'H') lie between them.

A unit is L long (stretcher) or W long (header, whose length is the stretcher's depth) along the
wall. running: every course stretchers, odd courses shifted by L/2. english: stretcher courses
and header courses alternating, the header courses shifted by W/2 (a queen closer at the ends).
flemish: headers and stretchers alternating in every course, odd courses shifted by (L + W)/2, so
that each header is centred on a stretcher below. Lengths in metres.
"""
from __future__ import annotations

import math

BONDS = ("running", "english", "flemish")


def pattern(bond: str, course: int, L: float, W: float):
    """(phase, units) of a course: the periodic sequence of (kind, length) starting at x = phase."""
    odd = course % 2
    if bond == "running":
        return (L / 2 if odd else 0.0), [("S", L)]
    if bond == "english":
        return ((W / 2, [("H", W)]) if odd else (0.0, [("S", L)]))
    return ((L + W) / 2 if odd else 0.0), [("H", W), ("S", L)]


def min_piece(L: float, W: float) -> float:
    """The shortest piece a course keeps at its ends: shorter ones merge into their neighbour
    (a queen closer, W/2, is kept)."""
    return min(L / 4, W / 2) * (1 - 1e-9)


def cut(bond: str, course: int, a: float, b: float, L: float, W: float, a_top=None, b_top=None,
        offset: float = 0.0):
    """Pieces (x0, x1, kind) of the course segment from ``a`` to ``b`` (m), the bond's joints
    counted from ``offset``. ``a_top``/``b_top``: where an inclined end lies at the top of the
    course (default: vertical ends); no joint falls within ``min_piece`` of either end, at the
    bottom or the top."""
    a_top = a if a_top is None else a_top
    b_top = b if b_top is None else b_top
    lo, hi = max(a, a_top), min(b, b_top)
    m = min_piece(L, W)
    phase, units = pattern(bond, course, L, W)
    period = sum(u[1] for u in units)
    x = offset + phase - period * math.ceil((offset + phase - min(a, a_top)) / period + 1)
    joints, kinds = [], []
    k = 0
    while x < max(b, b_top):
        kind, ln = units[k % len(units)]
        kinds.append((x, x + ln, kind))
        x += ln
        k += 1
        joints.append(x)
    inner = [j for j in joints if lo + m < j < hi - m]
    edges = [None] + inner + [None]
    out = []
    for i in range(len(edges) - 1):
        x0 = a if edges[i] is None else edges[i]
        x1 = b if edges[i + 1] is None else edges[i + 1]
        mid = ((lo if edges[i] is None else edges[i]) + (hi if edges[i + 1] is None else edges[i + 1])) / 2
        kind = next((kd for (u0, u1, kd) in kinds if u0 <= mid < u1), units[0][0])
        out.append((x0, x1, kind))
    return out
