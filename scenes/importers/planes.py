"""Planar facets of a repaired block, one least-squares plane each.

A *facet* is a set of the block's polygon faces that lie in one plane within the
flatness tolerance ``flat_tol`` (file units): a triangulated STL face becomes one
facet again, a warped quad stays one facet with its fitted plane, and a polygon
warped by more than ``flat_tol`` (e.g. a curved intrados drawn as one hexagon) is
split into its triangles, which are then regrouped with their coplanar neighbours.

Planes are ``n . x = d`` with ``n`` the outward unit normal (3D, or 2D for the edges
of an outline), fitted by SVD to the facet's corner points, so two blocks that
share a warped face's corners get the same plane.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def fit_plane(P: np.ndarray, outward: np.ndarray) -> tuple[np.ndarray, float, float]:
    """(n, d, max deviation) of the least-squares plane through points ``P`` (k, dim), ``n``
    on the side of ``outward``."""
    c = P.mean(axis=0)
    _, _, vt = np.linalg.svd(P - c)
    n = vt[-1]
    if n @ outward < 0:
        n = -n
    d = float(n @ c)
    return n, d, float(np.abs(P @ n - d).max())


def newell_normal(P: np.ndarray) -> np.ndarray:
    """Area vector of a 3D polygon (k, 3) by Newell's method: right-handed about its loop."""
    Q = np.roll(P, -1, axis=0)
    return 0.5 * np.cross(P - P.mean(axis=0), Q - P.mean(axis=0)).sum(axis=0)


def triangulate(P: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Triangles (t, 3) of local indices of a polygon (k, 3) seen along its normal ``n``,
    right-handed about ``n``: of all triangulations of the outline, the one whose worst
    triangle has the largest least angle (dynamic programming over the polygon, only
    triangles that are counter-clockwise in projection and hold no other corner), so a
    warped polygon is not cut into slivers whose planes mean nothing."""
    k = len(P)
    if k == 3:
        return np.array([[0, 1, 2]])
    if k == 4:  # the two diagonals; the DP below gives the same answer, slower
        return _quad(P, n)
    a = np.eye(3)[np.argmin(np.abs(n))]
    e1 = np.cross(a, n)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    xy = np.column_stack([(P - P.mean(axis=0)) @ e1, (P - P.mean(axis=0)) @ e2])

    def quality(i, j, m):
        u, v, w = xy[i], xy[j], xy[m]
        cr = (v - u)[0] * (w - u)[1] - (v - u)[1] * (w - u)[0]
        if cr <= 0:
            return -1.0
        for q in range(k):
            if q in (i, j, m):
                continue
            p = xy[q]
            s1 = (v - u)[0] * (p - u)[1] - (v - u)[1] * (p - u)[0]
            s2 = (w - v)[0] * (p - v)[1] - (w - v)[1] * (p - v)[0]
            s3 = (u - w)[0] * (p - w)[1] - (u - w)[1] * (p - w)[0]
            if s1 > 0 and s2 > 0 and s3 > 0:
                return -1.0
        A, B, C = P[i], P[j], P[m]
        ang = []
        for x, y, z in ((A, B, C), (B, C, A), (C, A, B)):
            d1, d2 = y - x, z - x
            c = d1 @ d2 / (np.linalg.norm(d1) * np.linalg.norm(d2) + 1e-300)
            ang.append(np.arccos(np.clip(c, -1, 1)))
        return float(min(ang))

    best = {}
    choice = {}
    for gap in range(2, k):
        for i in range(k - gap):
            j = i + gap
            if gap == 2:
                best[i, j] = quality(i, i + 1, j)
                choice[i, j] = i + 1
                continue
            top, arg = -np.inf, None
            for m in range(i + 1, j):
                q = quality(i, m, j)
                if q < 0:
                    continue
                left = best[i, m] if m - i >= 2 else np.inf
                right = best[m, j] if j - m >= 2 else np.inf
                v = min(q, left, right)
                if v > top:
                    top, arg = v, m
            best[i, j] = top
            choice[i, j] = arg
    if choice.get((0, k - 1)) is None or not best[0, k - 1] > 0:
        tri = np.array([[0, j, j + 1] for j in range(1, k - 1)])  # degenerate in projection: a fan
    else:
        tri, stack = [], [(0, k - 1)]
        while stack:
            i, j = stack.pop()
            if j - i < 2:
                continue
            m = choice[i, j]
            tri.append((i, m, j))
            stack += [(i, m), (m, j)]
        tri = np.array(tri)
    v = P[tri]
    s = np.einsum("ij,j->i", np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), n)
    tri[s < 0] = tri[s < 0][:, ::-1]
    return tri


def _least_angles(T: np.ndarray) -> np.ndarray:
    """Least interior angle of each triangle T (m, 3, 3)."""
    out = np.full(len(T), np.pi)
    for a, b, c in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        u, v = T[:, b] - T[:, a], T[:, c] - T[:, a]
        cosang = np.einsum("ij,ij->i", u, v) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1) + 1e-300)
        out = np.minimum(out, np.arccos(np.clip(cosang, -1, 1)))
    return out


def _quad(P: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Triangles of a quad: of its two diagonals, the one whose two triangles both turn the right
    way about ``n`` and whose worst least angle is larger."""
    best, arg = -1.0, None
    for tri in (np.array([[0, 1, 2], [0, 2, 3]]), np.array([[1, 2, 3], [1, 3, 0]])):
        T = P[tri]
        s = np.einsum("ij,j->i", np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]), n)
        if np.all(s > 0):
            q = float(_least_angles(T).min())
            if q > best:
                best, arg = q, tri
    return arg if arg is not None else np.array([[0, 1, 2], [0, 2, 3]])


@dataclass
class Facets:
    """Facets of one 3D block: ``tris`` (t, 3) vertex indices (outward), ``label`` (t,) the
    facet of each triangle, ``normal`` (f, 3), ``offset`` (f,), ``warp`` (f,) the largest
    distance of a facet corner from its plane (file units)."""

    tris: np.ndarray
    label: np.ndarray
    normal: np.ndarray
    offset: np.ndarray
    warp: np.ndarray

    def corners(self, f: int) -> np.ndarray:
        """Vertex indices of facet f."""
        return np.unique(self.tris[self.label == f])


def facets_3d(V: np.ndarray, faces: list, flat_tol: float, max_angle_deg: float = 20.0,
              split_warped: bool = True, face_tris: list | None = None) -> Facets:
    """Group the outward polygon ``faces`` of a block into planar facets (see the module).
    Without ``split_warped`` a polygon stays one facet however warped it is. ``face_tris``: each
    face's triangles (global indices) when already computed."""
    seeds = []  # (triangles (t, 3) global indices)
    for fi, f in enumerate(faces):
        P = V[f]
        area = newell_normal(P)
        if not np.linalg.norm(area) > 0:
            continue
        n, d, dev = fit_plane(P, area)
        tri = face_tris[fi] if face_tris is not None else np.asarray(f)[triangulate(P, n)]
        if dev <= flat_tol or not split_warped:
            seeds.append(tri)
        else:
            seeds.extend(t[None, :] for t in tri)
    # region growing over shared edges: merge two groups when their union fits one plane
    group = list(range(len(seeds)))
    members = {k: [k] for k in range(len(seeds))}
    pts = {k: np.unique(s) for k, s in enumerate(seeds)}
    nrm = {}
    for k, s in enumerate(seeds):
        a = sum(newell_normal(V[t]) for t in s)
        nrm[k] = a / np.linalg.norm(a)
    edge_owner = {}
    adj = set()
    for k, s in enumerate(seeds):
        for t in s:
            for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                e = (min(a, b), max(a, b))
                o = edge_owner.setdefault(e, k)
                if o != k:
                    adj.add((min(o, k), max(o, k)))
    cos_max = np.cos(np.deg2rad(max_angle_deg))

    def find(k):
        while group[k] != k:
            group[k] = group[group[k]]
            k = group[k]
        return k

    # try the most nearly coplanar neighbours first
    order = sorted(adj, key=lambda p: -float(nrm[p[0]] @ nrm[p[1]]))
    for a, b in order:
        ra, rb = find(a), find(b)
        if ra == rb or float(nrm[ra] @ nrm[rb]) < cos_max:
            continue
        P = V[np.union1d(pts[ra], pts[rb])]
        n, d, dev = fit_plane(P, nrm[ra] + nrm[rb])
        if dev <= flat_tol:
            group[rb] = ra
            members[ra] += members.pop(rb)
            pts[ra] = np.union1d(pts[ra], pts[rb])
            nrm[ra] = n
    roots = sorted({find(k) for k in range(len(seeds))})
    tris, label, normal, offset, warp = [], [], [], [], []
    for j, r in enumerate(roots):
        T = np.vstack([seeds[k] for k in members[r]])
        area = sum(newell_normal(V[t]) for t in T)
        n, d, dev = fit_plane(V[np.unique(T)], area)
        tris.append(T)
        label.append(np.full(len(T), j))
        normal.append(n)
        offset.append(d)
        warp.append(dev)
    return Facets(np.vstack(tris), np.concatenate(label), np.array(normal), np.array(offset), np.array(warp))


@dataclass
class Edges2D:
    """Facets of one 2D outline: ``loop`` (k,) vertex indices counter-clockwise as given, ``label``
    (k,) the facet of the edge loop[i] -> loop[i+1] (a facet may wrap around the loop's start), ``normal`` (f, 2), ``offset`` (f,), ``warp`` (f,)."""

    loop: np.ndarray
    label: np.ndarray
    normal: np.ndarray
    offset: np.ndarray
    warp: np.ndarray


def facets_2d(V: np.ndarray, loop: list, flat_tol: float) -> Edges2D:
    """Group consecutive edges of a counter-clockwise outline that lie on one line within
    ``flat_tol`` into one facet with its fitted line."""
    loop = np.asarray(loop)
    k = len(loop)
    P = V[loop]
    # start at a corner that is not on a straight run, so no facet wraps around the start
    def straight(i):
        a, b, c = P[i - 1], P[i], P[(i + 1) % k]
        u = c - a
        L = np.linalg.norm(u)
        return L > 0 and abs(u[0] * (b - a)[1] - u[1] * (b - a)[0]) / L <= flat_tol
    start = next((i for i in range(k) if not straight(i)), 0)
    loop = np.roll(loop, -start)
    P = V[loop]
    runs = [[0]]
    for i in range(1, k):
        cand = runs[-1] + [i]
        pts = P[cand + [(cand[-1] + 1) % k]]
        out = np.array([pts[-1][1] - pts[0][1], pts[0][0] - pts[-1][0]])
        if np.linalg.norm(out) > 0 and fit_plane(pts, out)[2] <= flat_tol:
            runs[-1] = cand
        else:
            runs.append([i])
    label = np.empty(k, dtype=int)
    normal, offset, warp = [], [], []
    for j, r in enumerate(runs):
        label[r] = j
        pts = P[r + [(r[-1] + 1) % k]]
        out = np.array([pts[-1][1] - pts[0][1], pts[0][0] - pts[-1][0]])
        n, d, dev = fit_plane(pts, out)
        normal.append(n)
        offset.append(d)
        warp.append(dev)
    # labels back in the order of the given loop (edge i runs from its corner i to corner i + 1)
    in_order = np.empty(k, dtype=int)
    in_order[(np.arange(k) + start) % k] = label
    return Edges2D(np.roll(loop, start), in_order, np.array(normal), np.array(offset), np.array(warp))
