"""Contact interfaces found from the block geometry alone.

Two blocks a, b touch where a face of a and a face of b lie in the same plane
(on the same line in 2D) with opposite outward normals and overlap with
positive area (length). With the scene's ``interfaces.angle_tolerance`` (degrees), faces up to
that angle from anti-parallel count too, where they lie within the scene's ``tolerance`` of
each other over all of their overlap (a CAD model's joints, which are seldom exactly plane
across a curved course); the interface then lies in block a's face plane, midway between the
two faces. Broad phase: :mod:`limit.geom._broadphase`; narrow phase:
vectorised face-pair tests and, in 3D, a tolerance-aware convex clipping
(:mod:`limit.geom._clip`).

Local frame of an interface (``normal``, ``t1``, ``t2``)
-------------------------------------------------------
* ``normal`` is the outward normal of block a, pointing into block b.
* 3D: ``t1 x t2 = normal``. For a rectangular contact ``t1`` runs along its
  longer edge, and ``l1``, ``l2`` are the half lengths along ``t1``, ``t2``
  (Baggio & Trovalusci's l_1, l_2). For any other polygon ``t1``, ``t2`` are the
  principal axes of its second moment of area (``t1`` the axis of least
  moment, i.e. along the longer extent) and ``l1``, ``l2`` its half extents
  along them.
* 2D: ``t1 = (n_y, -n_x)`` so that (t1, normal) is right-handed like (x, y);
  ``l1`` is the half length of the contact segment, ``l2`` half the scene
  thickness, and ``area`` is length x thickness (m^2).

``polygons[k]`` holds the contact polygon (3D: counter-clockwise about the
normal; 2D: the two end points) in world coordinates; ``local[k]`` the same
points in the (t1, t2) frame about the centroid (2D: a (2, 1) array of t1
coordinates).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from limit.geom import _broadphase as broadphase, _clip as clip, _facetable as facetable
from limit.geom.geometry import plane_basis, polygon_area_centroid

#: Faces count as anti-parallel when n_a . n_b < -(1 - ANGLE_TOL) (about 0.081 degrees), unless the
#: scene's ``interfaces.angle_tolerance`` is larger.
ANGLE_TOL = 1e-6


@dataclass
class Interfaces:
    dim: int
    a: np.ndarray          # (m,) index of block a (normal points out of a)
    b: np.ndarray          # (m,) index of block b
    normal: np.ndarray     # (m, d)
    t1: np.ndarray         # (m, d)
    t2: np.ndarray | None  # (m, 3) in 3D, None in 2D
    centroid: np.ndarray   # (m, d) m
    area: np.ndarray       # (m,) m^2
    l1: np.ndarray         # (m,) m
    l2: np.ndarray         # (m,) m
    is_rect: np.ndarray    # (m,) bool
    polygons: list         # m arrays (k, d), world coordinates
    local: list            # m arrays (k, 2) in 3D / (2, 1) in 2D, frame coordinates
    mu: np.ndarray         # (m,) friction coefficient
    #: (m,) cohesion c (Pa) and tensile strength ft (Pa) of the joint, zero for a dry joint
    #: (the scene's ``joints`` groups, :mod:`limit.model.joint_groups`)
    cohesion: np.ndarray | None = None
    tensile: np.ndarray | None = None
    #: (m,) compressive strength fc (Pa) of the joint, 0 for none (the blocks do not crush)
    fc: np.ndarray | None = None

    def __post_init__(self):
        m = len(self.a)
        if self.cohesion is None:
            self.cohesion = np.zeros(m)
        if self.tensile is None:
            self.tensile = np.zeros(m)
        if self.fc is None:
            self.fc = np.zeros(m)

    @property
    def bonded(self) -> bool:
        """True when any joint has cohesion or tensile strength."""
        return bool(np.any(self.cohesion > 0) or np.any(self.tensile > 0))

    def __len__(self) -> int:
        return len(self.a)

    def pairs(self, scene) -> list[tuple[str, str]]:
        return [(scene.blocks[i].id, scene.blocks[j].id) for i, j in zip(self.a, self.b)]


def pieces(blocks) -> tuple[list, np.ndarray]:
    """The convex pieces of ``blocks`` in block order (a compound block's parts, else its polytope)
    and the index of the block that owns each, (P,) non-decreasing."""
    polys = [p for b in blocks for p in b.pieces]
    owner = np.repeat(np.arange(len(blocks)), [len(b.pieces) for b in blocks])
    return polys, owner


def find_interfaces(scene) -> Interfaces:
    """All contact interfaces of ``scene`` (contacts between two fixed blocks excluded).

    Contacts are found between convex pieces: between a compound block's parts and the
    pieces of other blocks, never between two parts of one block. A pair of blocks has one
    interface per pair of touching pieces."""
    blocks = scene.blocks
    tol = scene.tolerance
    d = scene.dim
    polys, owner = pieces(blocks)
    ft = facetable.build(polys)
    lo, hi = broadphase.aabbs(polys)
    pa, pb = broadphase.candidate_pairs(lo, hi, tol)
    fixed = np.array([b.fixed for b in blocks])[owner]
    keep = ~(fixed[pa] & fixed[pb]) & (owner[pa] != owner[pb])
    pa, pb = pa[keep], pb[keep]

    angle = getattr(scene, "angle_tolerance", None)
    one_minus_cos = max(ANGLE_TOL, 1.0 - np.cos(np.radians(angle))) if angle else ANGLE_TOL
    fa, fb, pair = _facing_faces(ft, pa, pb, tol, one_minus_cos)
    if d == 2:
        res = _contacts_2d(ft, fa, fb, tol, scene.thickness)
    else:
        res = _contacts_3d(ft, fa, fb, tol)
    ok, fields = res
    pair = pair[ok]
    qa, qb = pa[pair], pb[pair]
    # At most one interface per pair of convex pieces and plane: keep the largest. (Two convex
    # pieces touch in one plane, but faces taken within an angle tolerance can meet in two: a
    # block across a ridge.)
    order = np.lexsort((-fields["area"], qb, qa))
    first = np.ones(len(order), bool)
    first[1:] = (qa[order][1:] != qa[order][:-1]) | (qb[order][1:] != qb[order][:-1])
    if one_minus_cos > ANGLE_TOL:
        kept = {}
        for pos, r in enumerate(order):
            key = (qa[r], qb[r])
            nr = fields["normal"][r]
            if first[pos]:
                kept[key] = [nr]
            elif all(nr @ m < 1.0 - ANGLE_TOL for m in kept[key]):
                first[pos] = True
                kept[key].append(nr)
    sel = order[first]
    sel = sel[np.lexsort((qb[sel], qa[sel]))]
    a, b = owner[qa], owner[qb]  # pieces are in block order, so a < b
    if len(polys) > len(blocks):  # compound blocks: one interface per plane of a block pair
        a, b, fields, sel = _merge_coplanar(a[sel], b[sel], {k: _take(v, sel) for k, v in fields.items()},
                                            d, tol, scene.thickness)
        a, b = a[sel], b[sel]
        sel = np.arange(len(sel))
    mu = np.full(len(sel), scene.friction)
    if scene.friction_pairs:
        for k, (i, j) in enumerate(zip(a[sel], b[sel])):
            key = (min(i, j), max(i, j))
            if key in scene.friction_pairs:
                mu[k] = scene.friction_pairs[key]
    coh, ten, fc = np.zeros(len(sel)), np.zeros(len(sel)), np.zeros(len(sel))
    for g in scene.joint_groups:  # the scene's "joints" (limit.model.joint_groups), in order, over the pairs
        hit = g.selects(a[sel], b[sel], [fields["polygons"][k] for k in sel])
        for arr, v in ((mu, g.mu), (coh, g.cohesion), (ten, g.tensile_strength), (fc, g.fc)):
            if v is not None:
                arr[hit] = v
    both = (fc > 0) & (ten > 0)
    if both.any():
        from limit.errors import SceneError

        k = int(np.flatnonzero(both)[0])
        raise SceneError(f"joints: the joint between '{blocks[a[sel][k]].id}' and '{blocks[b[sel][k]].id}' has both fc "
                         "and tensile_strength; crushing is modelled without tension (give one of them)")
    return Interfaces(
        dim=d, a=a[sel], b=b[sel],
        normal=fields["normal"][sel], t1=fields["t1"][sel],
        t2=None if d == 2 else fields["t2"][sel],
        centroid=fields["centroid"][sel], area=fields["area"][sel],
        l1=fields["l1"][sel], l2=fields["l2"][sel], is_rect=fields["is_rect"][sel],
        polygons=[fields["polygons"][k] for k in sel], local=[fields["local"][k] for k in sel],
        mu=mu, cohesion=coh, tensile=ten, fc=fc,
    )


def _take(v, idx):
    return [v[k] for k in idx] if isinstance(v, list) else v[idx]


def _merge_coplanar(a, b, fields, d, tol, thickness):
    """Merge the interfaces of one block pair that lie in one plane (a compound block's parts
    meeting one face, or one part meeting a neighbour's parts) into one whose contact polygon is
    the convex hull of theirs (2D: the segment that spans them) and whose ``area`` is the sum of
    theirs (the area in touch). For no-tension joints this is exact: a resultant within the hull
    of the union is a sum of resultants within the pieces, and the Coulomb cones of coplanar
    pieces sum to the cone of the whole. Returns (a, b, fields,
    order) with ``order`` sorting the result by (a, b)."""
    from scipy.spatial import ConvexHull

    m = len(a)
    pair_order = np.lexsort((b, a))
    groups, k = [], 0
    while k < m:
        j = k
        while j < m and a[pair_order[j]] == a[pair_order[k]] and b[pair_order[j]] == b[pair_order[k]]:
            j += 1
        rows = list(pair_order[k:j])
        while rows:  # one plane at a time
            r0 = rows[0]
            n0, c0 = fields["normal"][r0], fields["centroid"][r0]
            same = [r for r in rows if fields["normal"][r] @ n0 > 1.0 - ANGLE_TOL
                    and abs(n0 @ (fields["centroid"][r] - c0)) <= tol]
            groups.append(same)
            rows = [r for r in rows if r not in same]
        k = j
    if all(len(g) == 1 for g in groups):
        return a, b, fields, np.lexsort((b, a))
    out = {key: [] for key in fields}
    na, nb = [], []
    for g in groups:
        r0 = g[0]
        na.append(a[r0])
        nb.append(b[r0])
        if len(g) == 1:
            for key in fields:
                out[key].append(fields[key][r0])
            continue
        n, o = fields["normal"][r0], fields["centroid"][r0]
        pts = np.vstack([fields["polygons"][r] for r in g]) - o
        if d == 2:
            t = fields["t1"][r0]
            s = pts @ t
            lo, hi = float(s.min()), float(s.max())
            half = 0.5 * (hi - lo)
            cen = o + t * 0.5 * (lo + hi)
            new = dict(normal=n, t1=t, centroid=cen, area=2 * half * thickness, l1=half, l2=0.5 * thickness,
                       is_rect=True, polygons=np.array([cen - t * half, cen + t * half]), local=np.array([[-half], [half]]))
        else:
            e1, e2 = plane_basis(n)
            uv = np.column_stack([pts @ e1, pts @ e2])
            hull = uv[ConvexHull(uv).vertices]  # counter-clockwise about n
            one = _frame_fields(n[None], e1[None], e2[None], o[None], [hull], tol)
            new = {key: v[0] for key, v in one.items()}
        new["area"] = float(sum(fields["area"][r] for r in g))
        for key in fields:
            out[key].append(new[key])
    merged = {key: (v if isinstance(fields[key], list) else np.array(v)) for key, v in out.items()}
    na, nb = np.array(na), np.array(nb)
    return na, nb, merged, np.lexsort((nb, na))


def _facing_faces(ft, pa, pb, tol, one_minus_cos=ANGLE_TOL):
    """Face pairs (fa of block pa, fb of block pb) that are anti-parallel within ``one_minus_cos``
    (1 - cos of the angle between -n_a and n_b) and coplanar within ``tol``. A pair that is not
    anti-parallel within ANGLE_TOL passes where its planes may meet within ``tol`` over the faces
    (its centres apart by at most tol + sin(angle) x the faces' radii); :func:`_separation` then
    measures the gap over the overlap."""
    na = ft.ptr[pa + 1] - ft.ptr[pa]
    nb = ft.ptr[pb + 1] - ft.ptr[pb]
    cnt = na * nb
    pair = np.repeat(np.arange(len(pa)), cnt)
    k = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    fa = ft.ptr[pa][pair] + k // nb[pair]
    fb = ft.ptr[pb][pair] + k % nb[pair]
    dot = np.einsum("ij,ij->i", ft.normal[fa], ft.normal[fb])
    gap = np.einsum("ij,ij->i", ft.normal[fa], ft.point[fb] - ft.point[fa])  # distance between the planes
    ok = (dot < -(1.0 - ANGLE_TOL)) & (np.abs(gap) <= tol)
    if one_minus_cos > ANGLE_TOL:
        tilted = (dot < -(1.0 - one_minus_cos)) & ~ok
        if tilted.any():
            sin = np.sqrt(np.maximum(0.0, 1.0 - dot[tilted] ** 2))
            reach = tol + sin * (_radius(ft, fa[tilted]) + _radius(ft, fb[tilted]))
            ok[np.flatnonzero(tilted)[np.abs(gap[tilted]) <= reach]] = True
    return fa[ok], fb[ok], pair[ok]


def _radius(ft, faces) -> np.ndarray:
    """(m,) the largest distance from each face's centre to its corners."""
    return np.linalg.norm(ft.verts[faces] - ft.point[faces][:, None, :], axis=2).max(axis=1)


def _separation(ft, fa, fb, X, n) -> np.ndarray:
    """(m, k) the distance along ``n`` (face a's normal) from face a's plane to face b's plane at
    the points ``X`` (m, k, d): 0 where the faces touch, > 0 across a gap."""
    nb = ft.normal[fb]
    ta = ft.offset[fa][:, None] - np.einsum("mkd,md->mk", X, n)
    tb = (ft.offset[fb][:, None] - np.einsum("mkd,md->mk", X, nb)) / np.einsum("md,md->m", nb, n)[:, None]
    return tb - ta


def _contacts_2d(ft, fa, fb, tol, thickness):
    n = ft.normal[fa]
    t = np.column_stack([n[:, 1], -n[:, 0]])
    sa = np.einsum("ikd,id->ik", ft.verts[fa], t)
    sb = np.einsum("ikd,id->ik", ft.verts[fb], t)
    lo = np.maximum(sa.min(1), sb.min(1))
    hi = np.minimum(sa.max(1), sb.max(1))
    ok = hi - lo > tol
    tilted = np.einsum("ij,ij->i", n, ft.normal[fb]) >= -(1.0 - ANGLE_TOL)
    if (ok & tilted).any():  # tilted faces: they must meet within tol at both ends of the overlap
        r = np.flatnonzero(ok & tilted)
        p0 = ft.point[fa[r]] - np.einsum("ij,ij->i", ft.point[fa[r]], t[r])[:, None] * t[r]
        X = np.stack([p0 + lo[r, None] * t[r], p0 + hi[r, None] * t[r]], axis=1)
        ok[r] = np.abs(_separation(ft, fa[r], fb[r], X, n[r])).max(axis=1) <= tol
    n, t, lo, hi = n[ok], t[ok], lo[ok], hi[ok]
    fa, fb = fa[ok], fb[ok]
    # The contact line: midway between the two (coincident within tol) face lines.
    o = ft.point[fa] + 0.5 * n * np.einsum("ij,ij->i", n, ft.point[fb] - ft.point[fa])[:, None]
    mid = 0.5 * (lo + hi) - np.einsum("ij,ij->i", o, t)
    centroid = o + t * mid[:, None]
    half = 0.5 * (hi - lo)
    p0 = centroid - t * half[:, None]
    p1 = centroid + t * half[:, None]
    m = len(fa)
    fields = dict(
        normal=n, t1=t, centroid=centroid, area=2 * half * thickness, l1=half,
        l2=np.full(m, 0.5 * thickness), is_rect=np.ones(m, bool),
        polygons=[np.array([x, y]) for x, y in zip(p0, p1)],
        local=[np.array([[-h], [h]]) for h in half],
    )
    return ok, fields


def _contacts_3d(ft, fa, fb, tol):
    n = ft.normal[fa]
    m = len(fa)
    e1, e2 = plane_basis(n)  # in-plane basis, e1 x e2 = n
    # Local origin on the contact plane (midway between the two face planes), near the
    # face: small in-plane coordinates keep the polygon arithmetic accurate.
    o = ft.point[fa] + 0.5 * n * np.einsum("ij,ij->i", n, ft.point[fb] - ft.point[fa])[:, None]

    def project(faces):
        V = ft.verts[faces] - o[:, None, :]
        return np.stack([np.einsum("ikd,id->ik", V, e1), np.einsum("ikd,id->ik", V, e2)], axis=-1)

    ua, ub = project(fa), project(fb)
    polys = [None] * m
    ka_all, kb_all = ft.nvert[fa], ft.nvert[fb]
    for ka, kb in {(int(x), int(y)) for x, y in zip(ka_all, kb_all)}:
        rows = np.flatnonzero((ka_all == ka) & (kb_all == kb))
        # Face a is counter-clockwise about n in (e1, e2); face b about -n, so reverse it.
        res = clip.intersect(ua[rows, :ka], ub[rows, :kb][:, ::-1], tol)
        for r, p in zip(rows, res):
            polys[r] = p
    nv = np.array([len(p) for p in polys])
    area = np.zeros(m)
    diam = np.ones(m)
    for r in np.flatnonzero(nv >= 3):
        p = polys[r]
        area[r] = polygon_area_centroid(p)[0]
        diam[r] = np.linalg.norm(np.ptp(p, axis=0))
    # Positive area and a width (area / diameter) above the tolerance.
    ok = (nv >= 3) & (area / diam > tol)
    tilted = np.einsum("ij,ij->i", n, ft.normal[fb]) >= -(1.0 - ANGLE_TOL)
    for r in np.flatnonzero(ok & tilted):  # tilted faces: within tol of each other over the whole overlap
        p = polys[r]
        X = (o[r] + p[:, :1] * e1[r] + p[:, 1:2] * e2[r])[None]
        ok[r] = np.abs(_separation(ft, fa[r:r + 1], fb[r:r + 1], X, n[r:r + 1])).max() <= tol
    idx = np.flatnonzero(ok)
    ok_full = np.zeros(m, bool)
    ok_full[idx] = True
    return ok_full, _frame_fields(n[idx], e1[idx], e2[idx], o[idx], [polys[r] for r in idx], tol)


def _frame_fields(n, e1, e2, o, polys, tol) -> dict:
    """The interface fields (module docstring) of 3D contact polygons: ``polys[r]`` (k, 2) in the
    in-plane basis (e1[r], e2[r]) about the point o[r] of the plane with normal n[r] (e1 x e2 = n)."""
    counts = np.array([len(p) for p in polys], dtype=int)
    starts = np.cumsum(counts) - counts
    coords = np.vstack(polys) if len(polys) else np.empty((0, 2))
    nk = counts
    mm = len(polys)
    A = np.empty(mm)
    C = np.empty((mm, 2))
    t1 = np.empty((mm, 3))
    l1 = np.empty(mm)
    l2 = np.empty(mm)
    is_rect = np.zeros(mm, bool)
    local = [None] * mm
    world = [None] * mm
    corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    for k in np.unique(nk):
        rows = np.flatnonzero(nk == k)
        P = coords[starts[rows][:, None] + np.arange(k)]  # (r, k, 2)
        flip = polygon_area_centroid(P)[0] < 0  # make every polygon counter-clockwise about n
        P[flip] = P[flip, ::-1]
        a, cen = polygon_area_centroid(P)
        I = _second_moments(P, a, cen)
        rel = P - cen[:, None, :]
        rect, u_rect, box_c, half = _rectangle_fit(rel, a, tol)
        u = np.where(rect[:, None], u_rect, _principal_direction(I))
        u = np.where((u[:, :1] < -1e-12) | ((np.abs(u[:, :1]) <= 1e-12) & (u[:, 1:] < 0)), -u, u)
        w = np.column_stack([-u[:, 1], u[:, 0]])
        cen = cen + np.where(rect[:, None], box_c, 0.0)  # a rectangle is snapped to its exact box
        A[rows], C[rows], is_rect[rows] = a, cen, rect
        t1[rows] = u[:, :1] * e1[rows] + u[:, 1:] * e2[rows]
        for j, r in enumerate(rows):
            if rect[j]:
                loc = corners * half[j]
            else:
                q = rel[j]
                loc = np.column_stack([q @ u[j], q @ w[j]])
            l1[r], l2[r] = 0.5 * np.ptp(loc, axis=0)
            local[r] = loc
            plane = cen[j] + loc[:, :1] * u[j] + loc[:, 1:] * w[j]  # (e1, e2) coordinates
            world[r] = o[r] + plane[:, :1] * e1[r] + plane[:, 1:] * e2[r]
    cen3 = o + e1 * C[:, :1] + e2 * C[:, 1:]
    t2 = np.cross(n, t1)
    return dict(normal=n, t1=t1, t2=t2, centroid=cen3, area=A, l1=l1, l2=l2,
                is_rect=is_rect, polygons=world, local=local)


def _second_moments(P, a, cen):
    """Central second-moment tensor int(x x^T)dA (r, 2, 2) of counter-clockwise polygons
    P (r, k, 2) with areas a (r,) and centroids cen (r, 2) (polygon_area_centroid)."""
    Pn = np.roll(P, -1, axis=1)
    x, y, xn, yn = P[..., 0], P[..., 1], Pn[..., 0], Pn[..., 1]
    cr = x * yn - xn * y
    cx, cy = cen[:, 0], cen[:, 1]
    ixx = ((x * x + x * xn + xn * xn) * cr).sum(axis=1) / 12 - a * cx * cx
    iyy = ((y * y + y * yn + yn * yn) * cr).sum(axis=1) / 12 - a * cy * cy
    ixy = ((x * yn + 2 * x * y + 2 * xn * yn + xn * y) * cr).sum(axis=1) / 24 - a * cx * cy
    return np.stack([np.stack([ixx, ixy], -1), np.stack([ixy, iyy], -1)], -2)


def _principal_direction(I):
    """Unit axis of largest spread (largest eigenvalue of int x x^T dA), (r, 2)."""
    w, v = np.linalg.eigh(I)
    return v[:, :, 1]


def _rectangle_fit(rel, area, tol):
    """Which polygons (r, k, 2) are rectangles within the length tolerance ``tol``.

    The candidate rectangle is the bounding box aligned with the polygon's longest
    edge; the polygon counts as that rectangle when the box exceeds its area by no
    more than a strip of width ``tol`` around the perimeter. Returns
    (is_rect (r,), unit direction of the box's longer side (r, 2),
    box centre relative to the polygon centroid (r, 2), half sides (r, 2) with
    the longer first).
    """
    r = np.arange(len(rel))
    e = np.roll(rel, -1, axis=1) - rel
    L = np.linalg.norm(e, axis=2)
    j = np.argmax(L, axis=1)
    u = e[r, j] / L[r, j][:, None]
    w = np.column_stack([-u[:, 1], u[:, 0]])
    pu = np.einsum("rkj,rj->rk", rel, u)
    pw = np.einsum("rkj,rj->rk", rel, w)
    su, sw = np.ptp(pu, axis=1), np.ptp(pw, axis=1)
    rect = (su * sw - area) <= 2.0 * tol * (su + sw)
    ctr = (0.5 * (pu.max(1) + pu.min(1)))[:, None] * u + (0.5 * (pw.max(1) + pw.min(1)))[:, None] * w
    swap = sw > su * (1 + 1e-9)
    u = np.where(swap[:, None], w, u)
    half = 0.5 * np.where(swap[:, None], np.column_stack([sw, su]), np.column_stack([su, sw]))
    return rect, u, ctr, half
