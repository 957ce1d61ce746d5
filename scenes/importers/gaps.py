"""Contact faces across blocks: matching, and closing their gaps and overlaps.

Two faces of different blocks *match* when their outward normals are anti-parallel
within ``angle_deg``, each face's corners lie on average within ``gap`` (file units)
of the other's plane, and their projections on a common plane overlap with positive area.
Matched faces form clusters (a face under two neighbours links all three); each
cluster gets one common plane, the mid-plane between its two sides, so every face
of it lies exactly in that plane and the scene's contact detection finds the
interfaces. ``gap`` is signed in the reports: positive for a gap, negative for an
overlap (interpenetration).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Face:
    """One face of one block: ``block`` index, ``corners`` (k, d) points, ``tris`` (t, 3, d)
    its triangles (3D; in 2D the segment), ``normal`` (d,) outward unit, ``offset`` (n . x = offset)."""

    block: int
    corners: np.ndarray
    tris: np.ndarray | None
    normal: np.ndarray
    offset: float


def _clip(poly: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Part of the convex polygon ``poly`` (k, 2) left of the directed line a -> b."""
    if not len(poly):
        return poly
    e = b - a
    s = e[0] * (poly[:, 1] - a[1]) - e[1] * (poly[:, 0] - a[0])
    out = []
    k = len(poly)
    for i in range(k):
        j = (i + 1) % k
        if s[i] >= 0:
            out.append(poly[i])
        if (s[i] >= 0) != (s[j] >= 0):
            t = s[i] / (s[i] - s[j])
            out.append(poly[i] + t * (poly[j] - poly[i]))
    return np.array(out).reshape(-1, 2)


def _ccw(t: np.ndarray) -> np.ndarray:
    cr = (t[1, 0] - t[0, 0]) * (t[2, 1] - t[0, 1]) - (t[1, 1] - t[0, 1]) * (t[2, 0] - t[0, 0])
    return t if cr >= 0 else t[::-1]


def _area(p: np.ndarray) -> float:
    if len(p) < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _basis(n: np.ndarray) -> np.ndarray:
    """(3, 2) an orthonormal basis of the plane normal to the unit vector ``n``."""
    e1 = np.cross(np.eye(3)[np.argmin(np.abs(n))], n)
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(n, e1)])


def _overlaps(fa: Face, fb: Face, B: np.ndarray):
    """The overlaps (k, 2) of the faces' triangles projected on the basis ``B`` (3D)."""
    ta = [_ccw(t @ B) for t in fa.tris]
    tb = [_ccw(t @ B) for t in fb.tris]
    for p in ta:
        plo, phi = p.min(axis=0), p.max(axis=0)
        for q in tb:
            if np.any(q.max(axis=0) < plo) or np.any(q.min(axis=0) > phi):
                continue
            r = p
            for i in range(3):
                r = _clip(r, q[i], q[(i + 1) % 3])
            yield r


def overlap_measure(fa: Face, fb: Face) -> float:
    """Area (3D) or length (2D) of the overlap of the two faces' projections on a's plane."""
    n = fa.normal
    if len(n) == 2:
        t = np.array([n[1], -n[0]])
        a = np.sort(fa.corners @ t)
        b = np.sort(fb.corners @ t)
        return max(0.0, min(a[-1], b[-1]) - max(a[0], b[0]))
    return sum(_area(r) for r in _overlaps(fa, fb, _basis(n)))


def tilt_and_separation(fa: Face, fb: Face) -> tuple[float, float | None]:
    """(angle in degrees between -n_a and n_b, the largest distance along n_a from a's plane to
    b's plane over the overlap of the two faces' projections on a's plane; None without overlap).
    3D faces only (2D joints are lines: a tilt there is snapped or is not a joint)."""
    n, nb = fa.normal, fb.normal
    cos = float(np.clip(-(n @ nb), -1.0, 1.0))
    B = _basis(n)
    worst = None
    for r in _overlaps(fa, fb, B):
        if _area(r) > 0:
            X = r @ B.T + fa.offset * n  # the overlap's corners on a's plane
            worst = max(worst or 0.0, float(np.abs((fb.offset - X @ nb) / (nb @ n)).max()))
    return float(np.degrees(np.arccos(cos))), worst


def candidate_blocks(lo: np.ndarray, hi: np.ndarray, pad: float) -> list[tuple[int, int]]:
    """Pairs i < j of blocks whose bounding boxes (lo, hi: (n, d)) come within ``pad``."""
    order = np.argsort(lo[:, 0])
    out = []
    for pos, i in enumerate(order):
        for j in order[pos + 1:]:
            if lo[j, 0] > hi[i, 0] + pad:
                break
            if np.all(lo[j] <= hi[i] + pad) and np.all(lo[i] <= hi[j] + pad):
                out.append((min(i, j), max(i, j)))
    return out


@dataclass
class Snap:
    """The result of :func:`snap`: per face its new (normal, offset) or None when unmatched;
    ``pairs`` the matched (face a, face b, signed gap) triples; ``clusters`` lists of faces;
    ``loose`` the matched pairs left in different clusters (their faces get different planes,
    a few tenths of a degree apart across a curved course: the scene takes them as joints
    through ``interfaces.angle_tolerance``)."""

    planes: list
    pairs: list
    clusters: list
    loose: list = field(default_factory=list)


def snap(faces: list[Face], block_lo: np.ndarray, block_hi: np.ndarray, gap: float,
         angle_deg: float = 5.0, min_overlap: float = 0.0) -> Snap:
    """Match the faces of different blocks and give each cluster its common mid-plane."""
    by_block: dict[int, list[int]] = {}
    for k, f in enumerate(faces):
        by_block.setdefault(f.block, []).append(k)
    cos = np.cos(np.deg2rad(angle_deg))
    pairs = []
    for i, j in candidate_blocks(block_lo, block_hi, gap):
        A, B = by_block.get(i, []), by_block.get(j, [])
        if not A or not B:
            continue
        NA = np.array([faces[k].normal for k in A])
        NB = np.array([faces[k].normal for k in B])
        dots = NA @ NB.T
        for ia, ib in zip(*np.nonzero(dots < -cos)):
            fa, fb = faces[A[ia]], faces[B[ib]]
            # distances of each face's corners from the other's plane (outward of the other)
            da = fa.corners @ fb.normal - fb.offset  # a's corners seen from b: > 0 outside b
            db = fb.corners @ fa.normal - fa.offset
            if abs(da.mean()) > gap or abs(db.mean()) > gap:
                continue
            if overlap_measure(fa, fb) <= min_overlap:
                continue
            g = 0.5 * (float(da.mean()) + float(db.mean()))
            pairs.append((A[ia], B[ib], g))
    # clusters by union-find, best-fitting pairs first; two clusters join only while every two of
    # their faces stay (anti-)parallel within the angle tolerance and no block has two faces in
    # it, so that a chain of matches around a curved joint (a dome's conical bed) does not
    # flatten it into one plane
    parent = list(range(len(faces)))
    members = {k: [k] for k in range(len(faces))}

    def find(k):
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    kept, loose = [], []
    for a, b, g in sorted(pairs, key=lambda p: (-abs(float(faces[p[0]].normal @ faces[p[1]].normal)), abs(p[2]))):
        ra, rb = find(a), find(b)
        if ra != rb:
            Na = np.array([faces[k].normal for k in members[ra]])
            Nb = np.array([faces[k].normal for k in members[rb]])
            if np.abs(Na @ Nb.T).min() < cos:
                loose.append((a, b, g))
                continue
            if {faces[k].block for k in members[ra]} & {faces[k].block for k in members[rb]}:
                loose.append((a, b, g))
                continue  # one face per block in a joint
            parent[rb] = ra
            members[ra] += members.pop(rb)
        kept.append((a, b, g))
    pairs = kept
    groups = {r: m for r, m in members.items() if len(m) > 1}
    planes: list = [None] * len(faces)
    clusters = list(groups.values())
    for members in clusters:
        ref = faces[members[0]].normal
        side = np.array([1.0 if faces[k].normal @ ref > 0 else -1.0 for k in members])
        n = sum(s * faces[k].normal * len(faces[k].corners) for s, k in zip(side, members))
        n = n / np.linalg.norm(n)
        plus = np.vstack([faces[k].corners for s, k in zip(side, members) if s > 0]) @ n
        minus = np.vstack([faces[k].corners for s, k in zip(side, members) if s < 0]) @ n
        d = 0.5 * (plus.mean() + minus.mean())
        for s, k in zip(side, members):
            planes[k] = (s * n, s * d)
    return Snap(planes, pairs, clusters, loose)
