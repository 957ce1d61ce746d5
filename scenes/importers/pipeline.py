"""From raw blocks to scene blocks: repair, facets, contact snapping, convex blocks and compound blocks.

Lengths are in the file's units throughout (the command converts to metres at the end).
The tolerances, all lengths, follow from the blocks unless given (:class:`Options`):

* ``merge``: corners closer than this are one corner: 1e-6 of the model's diagonal.
* ``gap``: faces of two blocks whose planes are this close (on average over their corners),
  anti-parallel within ``angle_deg`` and overlapping are one joint, snapped to their
  mid-plane: ``gap_rel`` (0.15) times the median block width, a block's width being its
  least extent across one of its face planes.
* ``flat``: a face not in a joint that is warped by more than this is split into its
  triangles (its curvature kept); a flatter one keeps its least-squares plane:
  ``flat_rel`` (0.01) times the median block width.
* ``vol_tol``: a block whose convex hull exceeds its mesh volume by at most this fraction
  (default 0.01) is one convex block; any other block is a compound block of convex parts.
* ``thin_rel``: a compound block's piece thinner than this fraction (0.02) of the median block
  width (a sliver left by a cut), or than ``min_width`` (the command passes 1.5 times a given
  scene tolerance, which the loader requires a piece to exceed), is dropped, and the block's
  notes say how much volume went.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import ConvexHull

from limit.errors import SceneError
from scenes.importers import decompose, gaps as gapsmod, planes, repair as repairmod
from scenes.importers.readers import RawBlock

log = logging.getLogger("limit.import")


@dataclass
class Options:
    gap: float | None = None
    gap_rel: float = 0.15
    angle_deg: float = 5.0
    flat: float | None = None
    flat_rel: float = 0.01
    vol_tol: float = 0.01
    thin_rel: float = 0.02
    min_width: float = 0.0


@dataclass
class OutBlock:
    """A scene block in file units: ``vertices`` (convex) or ``parts`` (compound, a list of
    corner arrays); ``mesh_volume`` of the input mesh (3D) or outline area (2D); ``volume``
    of the output; ``hull_ratio`` the input's convex hull over its mesh volume."""

    id: str
    source: str
    tags: list
    vertices: np.ndarray | None
    parts: list | None
    mesh_volume: float
    volume: float
    hull_ratio: float
    notes: list = field(default_factory=list)


@dataclass
class Built:
    """The blocks and what the import did: tolerances used, gaps closed (signed, file units:
    > 0 gap, < 0 overlap), joints snapped, planarisation residual."""

    dim: int
    blocks: list
    tol: dict
    gap_max: float
    overlap_max: float
    n_joints: int
    residual: float
    warnings: list
    moved: float = 0.0
    times: dict = field(default_factory=dict)
    #: (count, largest angle in degrees, largest separation in file units) of the joints whose two
    #: faces kept different planes (3D; see :func:`_tilted`)
    tilted: tuple = (0, 0.0, 0.0)



def _tolerances(opts, widths) -> tuple[float, float, float]:
    """(median block width, gap tolerance, flatness tolerance), in the files' units: the options'
    values, else their defaults relative to the median width."""
    width = float(np.median(widths))
    gap = opts.gap if opts.gap is not None else opts.gap_rel * width
    flat = opts.flat if opts.flat is not None else opts.flat_rel * width
    return width, gap, flat

def _label(b) -> str:
    return f"block '{b.name}' ({b.source})"


def build(dim: int, raw: list[RawBlock], opts: Options) -> Built:
    return build_3d(raw, opts) if dim == 3 else build_2d(raw, opts)


def build_3d(raw: list[RawBlock], opts: Options) -> Built:
    import time

    times, t0 = {}, time.perf_counter()
    allv = np.vstack([b.vertices for b in raw])
    diag = float(np.linalg.norm(np.ptp(allv, axis=0)))
    merge = 1e-6 * diag
    solids = [repairmod.repair(b.name, b.source, b.tags, b.vertices, b.faces, merge) for b in raw]
    times["repair_s"], t0 = time.perf_counter() - t0, time.perf_counter()
    log.info("import: %d solids repaired (%.1f s); finding their planes", len(solids), times["repair_s"])
    fac = []
    widths = []
    for s in solids:
        F = planes.facets_3d(s.vertices, s.faces, merge, split_warped=False, face_tris=s.face_tris)
        proj = s.vertices @ F.normal.T - F.offset
        widths.append(float(np.min(-proj.min(axis=0))))
        fac.append(F)
    width, gap, flat = _tolerances(opts, widths)
    faces, owner = [], []
    for bi, (s, F) in enumerate(zip(solids, fac)):
        for k in range(len(F.offset)):
            T = F.tris[F.label == k]
            faces.append(gapsmod.Face(bi, s.vertices[np.unique(T)], s.vertices[T], F.normal[k], F.offset[k]))
            owner.append((bi, k))
    times["facets_s"], t0 = time.perf_counter() - t0, time.perf_counter()
    log.info("import: %d faces (%.1f s); matching joints", len(faces), times["facets_s"])
    lo = np.array([s.vertices.min(axis=0) for s in solids])
    hi = np.array([s.vertices.max(axis=0) for s in solids])
    snapped = gapsmod.snap(faces, lo, hi, gap, opts.angle_deg) if gap > 0 else gapsmod.Snap([None] * len(faces), [], [])
    plane_of = {owner[k]: p for k, p in enumerate(snapped.planes) if p is not None}
    tilted = _tilted(faces, snapped)
    times["joints_s"], t0 = time.perf_counter() - t0, time.perf_counter()
    log.info("import: %d pairs of facing faces (%.1f s); building the blocks' shapes", len(snapped.pairs),
             times["joints_s"])
    warnings = []
    out, worst, moved = [], 0.0, 0.0
    for bi, (s, F) in enumerate(zip(solids, fac)):
        # constrained facets: joints (snapped) and flat-enough free faces; the rest split into triangles
        fixed_planes, split_tris = {}, []
        for k in range(len(F.offset)):
            if (bi, k) in plane_of:
                fixed_planes[k] = plane_of[(bi, k)]
            elif F.warp[k] <= flat:
                fixed_planes[k] = (F.normal[k], float(F.offset[k]))
            else:
                split_tris.append(k)
        vp = [[] for _ in range(len(s.vertices))]
        for k, (n, d) in fixed_planes.items():
            for v in F.corners(k):
                vp[v].append((n, d))
        V2, res = decompose.planarize(s.vertices, vp)
        worst = max(worst, res)
        moved = max(moved, float(np.linalg.norm(V2 - s.vertices, axis=1).max()))
        notes = list(s.notes)
        if split_tris:
            notes.append(f"split {len(split_tris)} warped free face(s) into triangles")
        try:
            if s.hull_ratio <= 1 + opts.vol_tol:
                N = [n for n, _ in fixed_planes.values()]
                D = [d for _, d in fixed_planes.values()]
                for k in split_tris:
                    for t in F.tris[F.label == k]:
                        P = V2[t]
                        n = np.cross(P[1] - P[0], P[2] - P[0])
                        if np.linalg.norm(n) > 0:
                            n = n / np.linalg.norm(n)
                            N.append(n)
                            D.append(float(n @ P[0]))
                verts = decompose.polytope_vertices(np.array(N), np.array(D), V2.mean(axis=0), merge)
                vol = float(ConvexHull(verts).volume)
                out.append(OutBlock(s.name, s.source, s.tags, verts, None, s.volume, vol, s.hull_ratio, notes))
            else:
                parts = decompose.convex_pieces_3d(V2, F.tris, 1e-4 * width)
                parts = [decompose.snap_to_planes(p, list(fixed_planes.values()), max(flat, 0.5 * gap),
                                                  opts.angle_deg, merge) for p in parts]
                thin = max(opts.thin_rel * width, opts.min_width)
                parts, dropped = decompose.drop_thin(parts, thin)
                if dropped:
                    notes.append(f"dropped {len(dropped)} piece(s) thinner than {thin:.3g} "
                                 f"({100 * sum(dropped) / s.volume:.2g} % of its volume)")
                vol = float(sum(ConvexHull(p).volume for p in parts))
                if len(parts) == 1:
                    out.append(OutBlock(s.name, s.source, s.tags, parts[0], None, s.volume, vol, s.hull_ratio, notes))
                else:
                    out.append(OutBlock(s.name, s.source, s.tags, None, parts, s.volume, vol, s.hull_ratio, notes))
        except decompose.DecomposeError as exc:
            raise SceneError(f"{_label(s)}: {exc}") from None
        if abs(vol / s.volume - 1) > 0.05:
            warnings.append(f"{_label(s)}: its volume changed by {100 * (vol / s.volume - 1):+.1f} % "
                            "(snapped joints, flattened faces)")
    times["shapes_s"] = time.perf_counter() - t0
    g = np.array([p[2] for p in snapped.pairs]) if snapped.pairs else np.zeros(1)
    return Built(3, out, {"merge": merge, "gap": gap, "flat": flat, "angle_deg": opts.angle_deg,
                          "vol_tol": opts.vol_tol, "median_width": width},
                 float(max(g.max(), 0.0)), float(max(-g.min(), 0.0)), len(snapped.clusters), worst, warnings, moved,
                 times, tilted)


def _tilted(faces: list, snapped) -> tuple[int, float, float]:
    """(count, largest angle in degrees, largest separation in file units) of the matched face
    pairs that ended in different clusters, measured between their snapped planes over their
    overlap (:func:`gaps.tilt_and_separation`)."""
    def on_plane(k):
        f = faces[k]
        p = snapped.planes[k]
        return f if p is None else gapsmod.Face(f.block, f.corners, f.tris, np.asarray(p[0]), float(p[1]))

    out = [gapsmod.tilt_and_separation(on_plane(a), on_plane(b)) for a, b, _ in snapped.loose]
    out = [o for o in out if o[1] is not None]
    return (len(out), max((o[0] for o in out), default=0.0), max((o[1] for o in out), default=0.0))


def _outline(b: RawBlock, merge: float) -> tuple[np.ndarray, list]:
    """(corners (k, 2) counter-clockwise, notes) of a raw outline: repeated corners merged, a
    retraced tail dropped. SceneError for a self-touching outline or one with no area."""
    P = np.asarray(b.vertices, dtype=float)
    notes = []
    V, faces, merged = repairmod.merge_vertices(P, [list(range(len(P)))], merge)
    if not faces:
        raise SceneError(f"{_label(b)}: the outline has fewer than three distinct corners")
    loop = faces[0]
    seen, cut = {}, None
    for i, v in enumerate(loop):
        if v in seen:
            cut = i
            break
        seen[v] = i
    if cut is not None:
        if loop[cut] != loop[0]:
            raise SceneError(f"{_label(b)}: the outline touches itself at {V[loop[cut]].round(6).tolist()}")
        notes.append("dropped a retraced end of the outline")
        loop = loop[:cut]
    if len(loop) < 3:
        raise SceneError(f"{_label(b)}: the outline has fewer than three distinct corners")
    Q = V[loop]
    x, y = Q[:, 0] - Q[:, 0].mean(), Q[:, 1] - Q[:, 1].mean()
    area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    if not abs(area) > (1e-9 * np.ptp(Q, axis=0).max()) ** 2:
        raise SceneError(f"{_label(b)}: the outline encloses no area")
    if area < 0:
        Q = Q[::-1]
    return Q, notes


def _area(Q: np.ndarray) -> float:
    x, y = Q[:, 0] - Q[:, 0].mean(), Q[:, 1] - Q[:, 1].mean()
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def build_2d(raw: list[RawBlock], opts: Options) -> Built:
    allv = np.vstack([b.vertices for b in raw])
    diag = float(np.linalg.norm(np.ptp(allv, axis=0)))
    merge = 1e-6 * diag
    outl, fac, widths, notes_all = [], [], [], []
    for b in raw:
        Q, notes = _outline(b, merge)
        E = planes.facets_2d(Q, list(range(len(Q))), merge)
        proj = Q @ E.normal.T - E.offset
        widths.append(float(np.min(-proj.min(axis=0))))
        outl.append(Q)
        fac.append(E)
        notes_all.append(notes)
    width, gap, flat = _tolerances(opts, widths)
    faces, owner = [], []
    for bi, (Q, E) in enumerate(zip(outl, fac)):
        k = len(Q)
        for f in range(len(E.offset)):
            idx = np.flatnonzero(E.label == f)
            pts = Q[np.unique(np.r_[idx, (idx + 1) % k])]
            faces.append(gapsmod.Face(bi, pts, None, E.normal[f], E.offset[f]))
            owner.append((bi, f))
    lo = np.array([Q.min(axis=0) for Q in outl])
    hi = np.array([Q.max(axis=0) for Q in outl])
    snapped = gapsmod.snap(faces, lo, hi, gap, opts.angle_deg) if gap > 0 else gapsmod.Snap([None] * len(faces), [], [])
    plane_of = {owner[k]: p for k, p in enumerate(snapped.planes) if p is not None}
    out, worst, warnings, moved = [], 0.0, [], 0.0
    for bi, (b, Q, E) in enumerate(zip(raw, outl, fac)):
        k = len(Q)
        lines = {}
        for f in range(len(E.offset)):
            if (bi, f) in plane_of:
                lines[f] = plane_of[(bi, f)]
            elif E.warp[f] <= flat:
                lines[f] = (E.normal[f], float(E.offset[f]))
        vp = [[] for _ in range(k)]
        for i in range(k):
            for f in {int(E.label[i]), int(E.label[i - 1])}:  # edge i starts at corner i, edge i-1 ends there
                if f in lines:
                    vp[i].append(lines[f])
        Q2, res = decompose.planarize(Q, vp)
        worst = max(worst, res)
        moved = max(moved, float(np.linalg.norm(Q2 - Q, axis=1).max()))
        area0 = _area(Q)
        hull_ratio = float(ConvexHull(Q).volume) / area0
        label = f"block '{b.name}' ({b.source})"
        try:
            if hull_ratio <= 1 + opts.vol_tol:
                N, D = [], []
                for i in range(k):
                    f = E.label[i]
                    if f in lines:
                        n, d = lines[f]
                    else:
                        a, c = Q2[i], Q2[(i + 1) % k]
                        n = np.array([c[1] - a[1], a[0] - c[0]])
                        if not np.linalg.norm(n) > 0:
                            continue
                        n = n / np.linalg.norm(n)
                        d = float(n @ a)
                    N.append(n)
                    D.append(d)
                verts = decompose.polytope_vertices(np.array(N), np.array(D), Q2.mean(axis=0), merge)
                vol = float(ConvexHull(verts).volume)
                out.append(OutBlock(b.name, b.source, b.tags, verts, None, area0, vol, hull_ratio, notes_all[bi]))
            else:
                parts = decompose.convex_pieces_2d(Q2, 1e-9 * width)
                vol = float(sum(_area(p) for p in parts))
                out.append(OutBlock(b.name, b.source, b.tags, None, parts, area0, vol, hull_ratio, notes_all[bi]))
        except decompose.DecomposeError as exc:
            raise SceneError(f"{label}: {exc}") from None
        if abs(vol / area0 - 1) > 0.05:
            warnings.append(f"{label}: its area changed by {100 * (vol / area0 - 1):+.1f} % (snapped joints)")
    g = np.array([p[2] for p in snapped.pairs]) if snapped.pairs else np.zeros(1)
    return Built(2, out, {"merge": merge, "gap": gap, "flat": flat, "angle_deg": opts.angle_deg,
                          "vol_tol": opts.vol_tol, "median_width": width},
                 float(max(g.max(), 0.0)), float(max(-g.min(), 0.0)), len(snapped.clusters), worst, warnings, moved)
