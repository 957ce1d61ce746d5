"""Interface yield domains: the constraints ``Y x <= k`` on the interface actions x.

``k`` (n_faces,) is zero for dry joints. A joint with cohesion c and tensile strength ft (Pa, the
scene's ``joints`` groups) over its area A (m^2; 2D: length x thickness) has, per face:

* rocking: ``k = ft A``. The domain is exact for a stress field of uniform tension ft plus any
  compression (the blocks do not crush): (N + ft A, M) then lies in the no-tension domain, so
  every no-tension face ``-N + ... <= 0`` becomes ``-N + ... <= ft A``; N >= -ft A follows.
  A 2D block of width b on a joint with ft overturns at M = (b / 2)(N + ft A).
* sliding: ``k = c_fit c A`` (Mohr-Coulomb, |V| <= mu N + c A, with the polygon's fit factor).
* twisting: ``k = beta l c A`` (the paper's |T| <= beta l mu N with mu N + c A in place of mu N).
* crushing (``fc`` > 0, the paper's model): the compression is a stress block fc over a strip along
  the edge it turns about (2D: the thickness; 3D: the edge's length L), so the resultant's
  distance to that edge is at least N / (2 fc L) and the rocking face ``g <= b N`` becomes
  ``g <= b N - N^2 / (2 fc L)``, up to N = 2 fc L b (= fc A for a rectangle): replaced by the
  chords of :func:`crushing_chords` (RHS ``k`` > 0 but the first), never stronger than it and
  within 1 % of it. Exact for rectangles; for other polygons the strip is cut by the polygon's
  other edges, which this neglects. Not combined with tension.
* the vertex model: each of an interface's n corners takes A / n of its area (sliding
  ``d . f - c_fit mu fn <= c_fit c A / n``; normal ``-fn <= min(ft, c / mu) A / n``: a corner's
  tension cannot pass its Coulomb cone's apex, so without cohesion its corners carry none, where
  the paper's model lets a joint in compression overall carry ft over part of its area).

Cohesion and tension act on the whole area whatever the joint does elsewhere (a rocking joint
keeps its cohesion): the linear Mohr-Coulomb domain with a tension cut-off, written on the
resultants as the paper writes Coulomb's.

Two interface models share one interface, :class:`InterfaceModel`:

``"paper"`` (default): Baggio & Trovalusci's domain in the generalised stresses
  of :mod:`limit.model.kinematics` (x = r, per interface 2D ``[V, N, M]``, 3D
  ``[V1, V2, N, M1, M2, T]``). Faces per interface:

  * rocking, one face per edge of the contact polygon: the normal resultant
    stays inside the polygon (no tension). For the edge with outward normal
    ``a`` (local t1, t2 axes) at distance ``b`` from the centroid, the resultant
    point ``x = (-M2/N, M1/N)`` obeys ``a . x <= b``:
    ``-N + (a2 M1 - a1 M2) / b <= 0``. A rectangle gives the paper's four faces
    |M1| <= l2 N, |M2| <= l1 N; a 2D segment gives |M| <= l N (two faces).
  * sliding, ``n_slide`` faces ``d_j . V <= c mu N`` with directions d_j at
    angles j 2 pi / n_slide in the (t1, t2) plane. n_slide = 4, c = 1 is the
    paper (|V1| <= mu N, |V2| <= mu N: over-strong by up to sqrt 2 for sliding at
    45 degrees). With ``slide_fit="inscribed"`` c = cos(pi / n_slide): the
    polygon lies inside the friction circle (never over-strong; under-strength
    at most 1 - cos(pi / n_slide), e.g. 1.9 % for 16 faces). 2D: two faces.
  * twisting (3D), two faces |T| <= beta l mu N with beta = 2/3 and
    l = l1 + l2 (the paper: uniform pressure on a circle of radius l). For a
    non-rectangular polygon l1, l2 are its half extents along its principal
    axes (:mod:`limit.geom.interfaces`), which reduces to the paper's l1, l2 for a
    rectangle.

``"vertex"``: point contacts at the vertices of each contact polygon (2D: the
  two ends of the segment), each with its own normal force ``fn >= 0`` and a
  linearised friction pyramid (``n_slide`` faces as above) on its tangential
  force. x holds, per vertex, 2D ``[ft, fn]``, 3D ``[f1, f2, fn]`` in the
  interface's local frame; ``H`` sums them into the interface resultants r.

Flow rules: associative ``q = -Y^T lambda`` (normality: sliding dilates by mu);
non-associative ``q = G lambda``: the same columns with the normal component
of sliding and twisting faces removed (no dilatancy).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from limit.model import dims

ROCK, SLIDE, TWIST, NORMAL, TIE = 0, 1, 2, 3, 4
KIND_NAMES = {ROCK: "rock", SLIDE: "slide", TWIST: "twist", NORMAL: "normal", TIE: "tie"}
BETA = 2.0 / 3.0


@dataclass
class InterfaceModel:
    """Yield domain and flow rules of all interfaces.

    Y : (n_faces, n_x) sparse, the yield faces ``Y @ x <= 0``.
    G : (n_x, n_faces) sparse, non-associative flow directions.
    H : (m * nq, n_x) sparse, interface actions x -> generalised stresses r.
    kind : (n_faces,) face kind (ROCK, SLIDE, TWIST, NORMAL).
    iface : (n_faces,) interface of each face.
    x_iface : (n_x,) interface of each action component.
    x_is_moment : (n_x,) True where the component is a moment (N m).
    normal_col : (n_x,) True where the component is a normal force.
    k : (n_faces,) right-hand side of ``Y x <= k`` (N or N m), zero for dry joints.
    """

    name: str
    Y: sp.csr_matrix
    G: sp.csr_matrix
    H: sp.csr_matrix
    kind: np.ndarray
    iface: np.ndarray
    x_iface: np.ndarray
    x_is_moment: np.ndarray
    normal_col: np.ndarray
    k: np.ndarray | None = None

    def __post_init__(self):
        if self.k is None:
            self.k = np.zeros(self.Y.shape[0])

    @property
    def n_faces(self) -> int:
        return self.Y.shape[0]

    @property
    def n_x(self) -> int:
        return self.Y.shape[1]


def _slide_dirs(n_slide: int, fit: str):
    th = 2 * np.pi * np.arange(n_slide) / n_slide
    c = 1.0 if fit == "circumscribed" else np.cos(np.pi / n_slide)
    return np.column_stack([np.cos(th), np.sin(th)]), c


def resolve_fit(n_slide: int, fit: str) -> str:
    if fit == "auto":
        return "circumscribed" if n_slide == 4 else "inscribed"
    if fit not in ("circumscribed", "inscribed"):
        raise ValueError(f"slide_fit must be auto, circumscribed or inscribed, not {fit!r}")
    return fit


def build(I, model: str = "paper", n_slide: int = 4, slide_fit: str = "auto") -> InterfaceModel:
    """The interface model for interfaces ``I`` (:class:`limit.geom.interfaces.Interfaces`)."""
    if n_slide < 4 or n_slide % 2:
        raise ValueError("n_slide must be an even number >= 4")
    fit = resolve_fit(n_slide, slide_fit)
    if model == "paper":
        return _paper(I, n_slide, fit)
    if model == "vertex":
        return _vertex(I, n_slide, fit)
    raise ValueError(f"unknown interface model {model!r} (paper or vertex)")


class _Rows:
    """Accumulates sparse rows (faces) and their flow columns."""

    def __init__(self):
        self.r, self.c, self.v = [], [], []
        self.gr, self.gc, self.gv = [], [], []
        self.kind, self.iface, self.k = [], [], []
        self.n = 0

    def add(self, cols, vals, kind, iface, normal_cols, k=0.0):
        """Faces given as (nf, k) column indices and values; normal_cols (nf,) for G; ``k``
        (scalar or (nf,)) their right-hand sides."""
        cols = np.asarray(cols)
        vals = np.asarray(vals, dtype=float)
        nf = cols.shape[0]
        rid = self.n + np.arange(nf)
        self.r.append(np.repeat(rid, cols.shape[1]))
        self.c.append(cols.ravel())
        self.v.append(vals.ravel())
        # Non-associative flow: -row, without the normal component for sliding / twisting.
        g = -vals.copy()
        if kind in (SLIDE, TWIST):
            g[cols == np.asarray(normal_cols)[:, None]] = 0.0
        self.gr.append(cols.ravel())
        self.gc.append(np.repeat(rid, cols.shape[1]))
        self.gv.append(g.ravel())
        self.kind.append(np.full(nf, kind, np.int8))
        self.iface.append(np.asarray(iface))
        self.k.append(np.broadcast_to(np.asarray(k, dtype=float), (nf,)).copy())
        self.n += nf

    def matrices(self, n_x):
        cat = lambda a: np.concatenate(a) if a else np.empty(0)
        Y = sp.csr_matrix((cat(self.v), (cat(self.r).astype(int), cat(self.c).astype(int))), shape=(self.n, n_x))
        G = sp.csr_matrix((cat(self.gv), (cat(self.gr).astype(int), cat(self.gc).astype(int))), shape=(n_x, self.n))
        Y.eliminate_zeros()
        G.eliminate_zeros()
        return Y, G, cat(self.kind).astype(np.int8), cat(self.iface).astype(int), cat(self.k).astype(float)


def _edge_rows(loc, lengths: bool = False):
    """Outward unit normals a (k, 2) and distances b (k,) of a CCW polygon's edges (and their
    lengths (k,) with ``lengths``)."""
    e = np.roll(loc, -1, axis=0) - loc
    L = np.linalg.norm(e, axis=1)
    a = np.column_stack([e[:, 1], -e[:, 0]]) / L[:, None]
    b = np.einsum("ij,ij->i", a, loc)
    keep = L > 1e-12 * L.max()
    return (a[keep], b[keep], L[keep]) if lengths else (a[keep], b[keep])


#: chords of each crushing parabola: the inscribed polygon falls short of the exact domain by at
#: most 1 / CRUSH_CHORDS^2 of its largest moment (1 % with 10; see :func:`crushing_chords`)
CRUSH_CHORDS = 10


def crushing_chords(b: float, fc_L: float, n: int = CRUSH_CHORDS) -> tuple[np.ndarray, np.ndarray]:
    """(slopes s (n,), intercepts c (n,)) of the chords of f(N) = b N - N^2 / (2 fc L) on n equal
    steps of N from 0 to N_max = 2 fc L b, where f is 0 again. f is the largest moment about the
    contact's centroid, towards an edge at distance b (m) and of length L (m), that a normal force
    N carries when the compression is a stress block fc over a strip of the edge's length and
    depth N / (fc L) (``fc_L`` = fc L, N/m). ``g <= s_i N + c_i`` for every i is the polygon
    inscribed in the parabola's hypograph (f is concave): never stronger than the exact domain,
    weaker by at most (N_max / n)^2 / (8 fc L) = f_max / n^2 (f_max = b N_max / 4)."""
    Nm = 2.0 * fc_L * b
    N = Nm * np.arange(n + 1) / n
    f = b * N - N * N / (2.0 * fc_L)
    s = np.diff(f) / np.diff(N)
    return s, f[:-1] - s * N[:-1]


def _paper(I, n_slide, fit) -> InterfaceModel:
    m = len(I)
    dim = I.dim
    nq = dims.ndof(dim)
    k = np.arange(m)
    mu = I.mu
    cA, tA = I.cohesion * I.area, I.tensile * I.area  # (m,) N
    rows = _Rows()
    if dim == 2:
        V, N, M = 0, 1, 2
        l = I.l1
        base = (k * nq)[:, None]
        dry = I.fc <= 0  # crushing joints get the chords of their parabola instead
        for sgn in (1.0, -1.0):  # rocking about the ends s = +l and s = -l: +-M <= l (N + ft A)
            rows.add(base[dry] + [N, M], np.column_stack([-np.ones(dry.sum()), np.full(dry.sum(), sgn) / l[dry]]),
                     ROCK, k[dry], k[dry] * nq + N, tA[dry])
        for kk in np.flatnonzero(~dry):  # |M| <= l N - N^2 / (2 fc t), t the thickness
            sl, cl = crushing_chords(l[kk], I.fc[kk] * I.area[kk] / (2.0 * l[kk]))
            for sgn in (1.0, -1.0):
                rows.add(kk * nq + np.tile([N, M], (sl.size, 1)), np.column_stack([-sl / l[kk], np.full(sl.size, sgn / l[kk])]),
                         ROCK, np.full(sl.size, kk), np.full(sl.size, kk * nq + N), cl / l[kk])
        for sgn in (1.0, -1.0):  # sliding: +-V <= mu N + c A
            rows.add(base + [V, N], np.column_stack([np.full(m, sgn), -mu]), SLIDE, k, k * nq + N, cA)
    else:
        V1, V2, N, M1, M2, T = range(6)
        cols, vals, owner, rhs = [], [], [], []
        for kk in range(m):
            a, b, L = _edge_rows(I.local[kk], lengths=True)
            ne = len(b)
            if I.fc[kk] > 0:  # a chord per step of each edge's parabola: a . x <= b - N / (2 fc L)
                for e in range(ne):
                    sl, cl = crushing_chords(b[e], I.fc[kk] * L[e])
                    cols.append(kk * nq + np.tile([N, M1, M2], (sl.size, 1)))
                    vals.append(np.column_stack([-sl / b[e], np.full(sl.size, a[e, 1] / b[e]),
                                                 np.full(sl.size, -a[e, 0] / b[e])]))
                    owner.append(np.full(sl.size, kk))
                    rhs.append(cl / b[e])
                continue
            cols.append(kk * nq + np.tile([N, M1, M2], (ne, 1)))
            vals.append(np.column_stack([-np.ones(ne), a[:, 1] / b, -a[:, 0] / b]))
            owner.append(np.full(ne, kk))
            rhs.append(np.full(ne, tA[kk]))
        own = np.concatenate(owner)
        rows.add(np.vstack(cols), np.vstack(vals), ROCK, own, own * nq + N, np.concatenate(rhs))
        base = (k * nq)[:, None]
        dirs, c = _slide_dirs(n_slide, fit)
        for d in dirs:
            rows.add(base + [V1, V2, N], np.column_stack([np.full(m, d[0]), np.full(m, d[1]), -c * mu]),
                     SLIDE, k, k * nq + N, c * cA)
        lt = BETA * (I.l1 + I.l2)
        for sgn in (1.0, -1.0):
            rows.add(base + [N, T], np.column_stack([-lt * mu, np.full(m, sgn)]), TWIST, k, k * nq + N, lt * cA)
    n_x = m * nq
    Y, G, kind, iface, kr = rows.matrices(n_x)
    comp = np.tile(np.arange(nq), m)
    is_moment = comp >= dims.first_moment_index(dim)
    normal = comp == dims.normal_index(dim)
    return InterfaceModel("paper", Y, G, sp.identity(n_x, format="csr"), kind, iface,
                          np.repeat(k, nq), is_moment, normal, kr)


def _vertex(I, n_slide, fit) -> InterfaceModel:
    if np.any(I.fc > 0):
        from limit.errors import SceneError

        raise SceneError("joints: crushing (fc) is modelled in the paper's interface model only (the default; "
                         "not --model vertex)")
    m = len(I)
    dim = I.dim
    nq = dims.ndof(dim)
    nv = np.array([len(p) for p in I.local])
    vptr = np.concatenate([[0], np.cumsum(nv)])
    nvert = int(vptr[-1])
    owner = np.repeat(np.arange(m), nv)
    loc = np.vstack(I.local)  # (nvert, 1) in 2D, (nvert, 2) in 3D
    share = (I.area / nv)[owner]  # (nvert,) m^2: each corner's share of its interface's area
    mu_v = I.mu[owner]
    with np.errstate(divide="ignore", invalid="ignore"):  # a corner's tension stops at its cone's apex, c / mu
        apex = np.where(mu_v > 0, I.cohesion[owner] / mu_v, np.inf)
    cA, tA = I.cohesion[owner] * share, np.minimum(I.tensile[owner], apex) * share
    rows = _Rows()
    if dim == 2:
        nc = 2  # [ft, fn]
        x0 = np.arange(nvert) * nc
        ft, fn = x0, x0 + 1
        rows.add(fn[:, None], -np.ones((nvert, 1)), NORMAL, owner, fn, tA)
        for sgn in (1.0, -1.0):
            rows.add(np.column_stack([ft, fn]), np.column_stack([np.full(nvert, sgn), -I.mu[owner]]),
                     SLIDE, owner, fn, cA)
        s = loc[:, 0]
        hr = np.concatenate([owner * nq + 0, owner * nq + 1, owner * nq + 2])
        hc = np.concatenate([ft, fn, fn])
        hv = np.concatenate([np.ones(nvert), np.ones(nvert), s])
        is_moment = np.zeros(nvert * nc, bool)
    else:
        nc = 3  # [f1, f2, fn]
        x0 = np.arange(nvert) * nc
        f1, f2, fn = x0, x0 + 1, x0 + 2
        rows.add(fn[:, None], -np.ones((nvert, 1)), NORMAL, owner, fn, tA)
        dirs, c = _slide_dirs(n_slide, fit)
        for d in dirs:
            rows.add(np.column_stack([f1, f2, fn]),
                     np.column_stack([np.full(nvert, d[0]), np.full(nvert, d[1]), -c * I.mu[owner]]),
                     SLIDE, owner, fn, c * cA)
        x1, x2 = loc[:, 0], loc[:, 1]
        b = owner * nq
        # r = [V1, V2, N, M1, M2, T] = [sum f1, sum f2, sum fn, sum x2 fn, -sum x1 fn, sum (x1 f2 - x2 f1)]
        hr = np.concatenate([b, b + 1, b + 2, b + 3, b + 4, b + 5, b + 5])
        hc = np.concatenate([f1, f2, fn, fn, fn, f2, f1])
        hv = np.concatenate([np.ones(nvert), np.ones(nvert), np.ones(nvert), x2, -x1, x1, -x2])
        is_moment = np.zeros(nvert * nc, bool)
    n_x = nvert * nc
    Y, G, kind, iface, kr = rows.matrices(n_x)
    H = sp.csr_matrix((hv, (hr, hc)), shape=(m * nq, n_x))
    comp = np.tile(np.arange(nc), nvert)
    normal = comp == nc - 1
    return InterfaceModel("vertex", Y, G, H, kind, iface, np.repeat(owner, nc), is_moment, normal, kr)


def with_ties(model: InterfaceModel, capacities: np.ndarray) -> InterfaceModel:
    """``model`` with one action per tie appended (its tension T, N; :mod:`limit.model.ties`) and
    two yield rows each, ``-T <= 0`` and ``T <= capacity`` (kind TIE, associative flow). The
    ties' actions and rows form groups of their own after the interfaces' (``x_iface`` and
    ``iface`` m, m + 1, ...); ``H`` gives them no interface stress."""
    cap = np.asarray(capacities, dtype=float)
    nt = cap.size
    if not nt:
        return model
    n_x, nf = model.n_x, model.n_faces
    m = int(model.x_iface.max(initial=-1)) + 1
    j = np.arange(nt)
    Yt = sp.csr_matrix((np.tile([-1.0, 1.0], nt), (np.arange(2 * nt), np.repeat(j, 2))), shape=(2 * nt, nt))
    Y = sp.bmat([[model.Y, None], [None, Yt]], format="csr")
    G = sp.bmat([[model.G, None], [None, -Yt.T]], format="csr")
    H = sp.hstack([model.H, sp.csr_matrix((model.H.shape[0], nt))]).tocsr()
    return InterfaceModel(model.name, Y, G, H, np.concatenate([model.kind, np.full(2 * nt, TIE, np.int8)]),
                          np.concatenate([model.iface, m + np.repeat(j, 2)]),
                          np.concatenate([model.x_iface, m + j]), np.concatenate([model.x_is_moment, np.zeros(nt, bool)]),
                          np.concatenate([model.normal_col, np.zeros(nt, bool)]),
                          np.concatenate([model.k, np.column_stack([np.zeros(nt), cap]).ravel()]))

