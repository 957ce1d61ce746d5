"""Block geometry from planes: convex polytopes, planarised meshes, and convex pieces of concave blocks.

* :func:`polytope_vertices`: the convex polytope ``{x : N x <= d}`` (3D or 2D) as its corner
  points, by scipy's HalfspaceIntersection around the Chebyshev centre (a small LP).
* :func:`planarize`: moves each mesh vertex the least distance that puts it on the planes of
  its constrained facets (exactly, where it has at most three independent ones).
* :func:`convex_pieces_3d`: exact convex pieces of a closed triangle mesh, cut recursively
  through its most reflex edge by the plane that bisects the edge's dihedral angle
  (trimesh's ``slice_mesh_plane`` with capping); the pieces' volumes sum to the mesh's.
* :func:`convex_pieces_2d`: convex pieces of a simple polygon (earcut triangles merged
  across diagonals while the union stays convex, Hertel & Mehlhorn).

Lengths are in the file's units; ``tol`` arguments are lengths.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError


class DecomposeError(ValueError):
    """A block whose geometry cannot be turned into convex pieces (the message says why)."""


def chebyshev_centre(N: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, float]:
    """(centre, radius) of the largest ball in ``{x : N x <= d}`` (rows of N unit vectors)."""
    dim = N.shape[1]
    res = linprog(np.r_[np.zeros(dim), -1.0], A_ub=np.hstack([N, np.ones((len(N), 1))]), b_ub=d,
                  bounds=[(None, None)] * dim + [(0, None)], method="highs")
    if res.status != 0:
        return np.zeros(dim), 0.0
    return res.x[:dim], float(res.x[-1])


def polytope_vertices(N: np.ndarray, d: np.ndarray, origin: np.ndarray, merge_tol: float) -> np.ndarray:
    """Corners (m, dim) of ``{x : N x <= d}``, computed about ``origin`` for accuracy; corners
    closer than ``merge_tol`` merged. DecomposeError when the set is empty, flat or unbounded."""
    N = np.asarray(N, dtype=float)
    d = np.asarray(d, dtype=float) - N @ origin
    # the origin itself when it lies well inside (a piece's own centroid), else the Chebyshev centre
    c, r = np.zeros(N.shape[1]), float(d.min())
    if not r > 1e-3 * float(np.abs(d).max()):
        c, r = chebyshev_centre(N, d)
    if not r > merge_tol:
        raise DecomposeError("its face planes enclose no volume")
    try:
        hs = HalfspaceIntersection(np.hstack([N, -d[:, None]]), c)
    except QhullError as exc:
        raise DecomposeError(f"its face planes do not bound a polytope ({str(exc).splitlines()[0]})") from None
    P = hs.intersections
    if not np.all(np.isfinite(P)) or np.abs(P).max() > 1e6 * (np.abs(d).max() + r):
        raise DecomposeError("its face planes do not close it (unbounded)")
    P = _merge_points(P, merge_tol)
    return P + origin


def snap_to_planes(P: np.ndarray, planes: list, dist: float, angle_deg: float, merge_tol: float) -> np.ndarray:
    """Corners of the convex piece with corners ``P`` (k, 3) rebuilt from planes: each triangle of
    its hull whose corners lie within ``dist`` of one of the block's ``planes`` (list of (n, d):
    its joints and flat faces), its normal within ``angle_deg``, takes that plane exactly, the others keep their own. So a
    piece's face on a joint is exactly in the joint's plane even where a corner of the mesh met
    more planes than it could lie on. The piece is kept as it was when the rebuilt one's volume
    differs by more than 1 %."""
    h = ConvexHull(P)
    N = h.equations[:, :-1].copy()
    D = -h.equations[:, -1].copy()
    if planes:
        N0 = np.array([n for n, _ in planes])
        D0 = np.array([d for _, d in planes])
        # each hull triangle's farthest corner from each plane
        far = np.abs(np.einsum("tkd,pd->tpk", P[h.simplices], N0) - D0[None, :, None]).max(axis=2)
        score = np.where(N @ N0.T > np.cos(np.deg2rad(angle_deg)), far, np.inf)
        j = score.argmin(axis=1)
        ok = score[np.arange(len(N)), j] <= dist
        N[ok], D[ok] = N0[j[ok]], D0[j[ok]]
    try:
        Q = polytope_vertices(N, D, P.mean(axis=0), merge_tol)
        if abs(ConvexHull(Q).volume - h.volume) <= 0.01 * h.volume:
            return Q
    except (DecomposeError, QhullError):
        pass
    return P[h.vertices]


def width(P: np.ndarray) -> float:
    """Least extent of the convex hull of ``P`` across one of its face planes."""
    h = ConvexHull(P)
    proj = P @ h.equations[:, :-1].T
    return float((proj.max(axis=0) - proj.min(axis=0)).min())


def drop_thin(parts: list, min_width: float) -> tuple[list, list]:
    """(kept parts, volumes of the dropped ones): parts thinner than ``min_width`` are dropped,
    unless that would leave none."""
    keep, dropped = [], []
    for p in parts:
        if width(p) < min_width:
            dropped.append(float(ConvexHull(p).volume))
        else:
            keep.append(p)
    return (keep, dropped) if keep else (parts, [])


def _merge_points(P: np.ndarray, tol: float) -> np.ndarray:
    from scipy.cluster.hierarchy import fcluster, linkage

    if len(P) < 2:
        return P
    label = fcluster(linkage(P, method="single"), t=tol, criterion="distance") - 1
    n = int(label.max()) + 1
    W = np.zeros((n, P.shape[1]))
    np.add.at(W, label, P)
    return W / np.bincount(label, minlength=n)[:, None]


def planarize(V: np.ndarray, vertex_planes: list) -> tuple[np.ndarray, float]:
    """(new vertices, largest residual): each vertex ``V[i]`` moved by the least-norm step that
    puts it on the planes ``vertex_planes[i]`` (a list of (n, d)); least squares when they are
    more than it can meet. The residual is the largest distance left to one of its planes."""
    W = V.copy()
    worst = 0.0
    for i, planes in enumerate(vertex_planes):
        if not planes:
            continue
        N = np.array([p[0] for p in planes])
        d = np.array([p[1] for p in planes])
        # rcond 0.2: directions where two planes are within about 23 degrees (tan(23/2) = 0.2) stay put
        step, *_ = np.linalg.lstsq(N, d - N @ V[i], rcond=0.2)
        W[i] = V[i] + step
        worst = max(worst, float(np.abs(N @ W[i] - d).max()))
    return W, worst


def _components(mesh):
    import trimesh

    if len(mesh.faces) == 0:
        return []
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, node_count=len(mesh.faces))
    if labels.max() == 0:
        return [mesh]
    return [mesh.submesh([np.flatnonzero(labels == k)], append=True) for k in np.unique(labels)]


def convex_pieces_3d(V: np.ndarray, tris: np.ndarray, tol: float, max_pieces: int = 64,
                     sliver: float = 1e-4) -> list[np.ndarray]:
    """Convex pieces of the closed outward triangle mesh (V, tris): a list of corner arrays
    (k, 3), each the corners of its piece's convex hull. An edge counts as reflex when the far
    corner of one triangle lies more than ``tol`` outside the other's plane. A piece under
    ``sliver`` of the mesh volume (left by a cut near a corner) is dropped."""
    import trimesh

    todo = [trimesh.Trimesh(V, tris, process=False)]
    todo[0].merge_vertices(digits_vertex=None)
    volume0 = float(todo[0].volume)
    done = []
    while todo:
        m = todo.pop()
        if len(m.faces) < 4 or not m.volume > sliver * volume0:
            continue  # a sliver left by a cut near a corner
        try:
            hull = ConvexHull(m.vertices)
        except QhullError:
            raise DecomposeError("a cut left a flat piece") from None
        if hull.volume <= m.volume + tol * np.sqrt(hull.area) ** 2 * 1e-3 or hull.volume <= m.volume * (1 + 1e-9):
            done.append(m.vertices[hull.vertices])
            continue
        if len(done) + len(todo) >= max_pieces:
            raise DecomposeError(f"more than {max_pieces} convex pieces needed")
        proj = m.face_adjacency_projections
        k = int(np.argmax(proj))
        if not proj[k] > tol:
            # no reflex edge above the tolerance: the piece is convex within it
            done.append(m.vertices[hull.vertices])
            continue
        f1, f2 = m.face_adjacency[k]
        e = m.face_adjacency_edges[k]
        axis = m.vertices[e[1]] - m.vertices[e[0]]
        axis /= np.linalg.norm(axis)
        # the cut plane holds the edge and the sum of the two faces' outward normals (the notch's
        # opening direction): it bisects the solid's angle at the edge, each side then convex there
        b = m.face_normals[f1] + m.face_normals[f2]
        b = b - (b @ axis) * axis
        if not np.linalg.norm(b) > 0:
            raise DecomposeError("a folded edge (two faces back to back)")
        n = np.cross(axis, b / np.linalg.norm(b))
        o = 0.5 * (m.vertices[e[0]] + m.vertices[e[1]])
        parts = []
        for s in (1.0, -1.0):
            try:
                piece = trimesh.intersections.slice_mesh_plane(m, s * n, o, cap=True)
            except Exception as exc:  # trimesh's capping can fail on degenerate sections
                raise DecomposeError(f"a cut through a reflex edge failed ({type(exc).__name__}: {exc})") from None
            parts.extend(_components(piece))
        vol = sum(p.volume for p in parts)
        if abs(vol - m.volume) > 1e-6 * m.volume or len(parts) < 2:
            raise DecomposeError(f"a cut through a reflex edge lost volume ({vol:.6g} of {m.volume:.6g})")
        todo.extend(parts)
    return done


def convex_pieces_2d(P: np.ndarray, tol: float) -> list[np.ndarray]:
    """Convex pieces (list of (k, 2) counter-clockwise) of the simple counter-clockwise polygon P."""
    import mapbox_earcut as earcut

    tri = earcut.triangulate_float64(P - P.mean(axis=0), np.array([len(P)], dtype=np.uint32)).reshape(-1, 3)
    if not len(tri):
        raise DecomposeError("its outline cannot be triangulated (self-intersecting?)")
    polys = []
    for t in tri:
        a, b, c = P[t]
        cr = (b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]
        polys.append(list(t) if cr > 0 else list(t[::-1]))

    def convex(loop):
        Q = P[loop]
        R = np.roll(Q, -1, axis=0)
        S = np.roll(Q, -2, axis=0)
        cr = (R - Q)[:, 0] * (S - R)[:, 1] - (R - Q)[:, 1] * (S - R)[:, 0]
        return np.all(cr >= -tol * np.linalg.norm(R - Q, axis=1))

    merged = True
    while merged:
        merged = False
        for i in range(len(polys)):
            for j in range(i + 1, len(polys)):
                a, b = polys[i], polys[j]
                for k in range(len(a)):
                    u, v = a[k], a[(k + 1) % len(a)]
                    if v in b and b[(b.index(v) + 1) % len(b)] == u:
                        # join b into a across the diagonal u-v
                        bi = b.index(u)
                        rest = [b[(bi + m) % len(b)] for m in range(1, len(b) - 1)]
                        loop = a[:k + 1] + rest + a[k + 1:]
                        if convex(loop):
                            polys[i] = loop
                            del polys[j]
                            merged = True
                        break
                if merged:
                    break
            if merged:
                break
    return [P[p] for p in polys]
