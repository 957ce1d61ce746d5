"""Vaults: a barrel vault of voussoir rings on two abutments, and a cross (groin) vault on four corner
piers.

3D, z up; lengths in metres. Voussoirs have radial joints and flat intrados and extrados (chords),
so every face is planar and neighbours share their faces exactly.
"""
from __future__ import annotations

import math

import numpy as np

from limit.errors import SceneError

from .. import builders as B
from ._common import box3, choice, count, finish, halfspace_vertices, outline_block, positive


def barrel_vault(span=2.0, thickness=0.2, n=9, rings=4, ring_width=0.3, kind="semicircular", rise=None,
                 stagger=True, abutment_width=None, mu=0.8, density=2000.0, name=None) -> dict:
    """A barrel vault of voussoir rings between two fixed abutments; returns a ``blockscene/1`` dict.

    The rings stand side by side along y; each is an arch in the (x, z) plane.
    span: clear span between the springing points (m); the intrados springs at height 0.
    thickness: ring thickness (m).
    n: voussoirs per ring.
    rings: rings along y.
    ring_width: each ring's width along y (m).
    kind: 'semicircular' or 'segmental'.
    rise: segmental only, the intrados rise (m; default span/4).
    stagger: odd rings are shifted by half a voussoir (a half voussoir at each springing), so that
        the radial joints of neighbouring rings alternate; False aligns them (a row of arches).
    abutment_width: along x (m; default the ring's horizontal extent at the springing).
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: 'r{ring}-{k}' (k from the right springing), tagged 'voussoir', 'ring-{ring}', the end
    ones 'springing', the crown one(s) 'key'; fixed abutments 'abutment-right', 'abutment-left'.
    Loads: self weight (dead), 1 g along +x (live), in the rings' plane.
    """
    params = dict(span=span, thickness=thickness, n=n, rings=rings, ring_width=ring_width, kind=kind, rise=rise,
                  stagger=stagger, abutment_width=abutment_width, mu=mu, density=density)
    choice("kind", kind, ("semicircular", "segmental"))
    s, t = positive("span", span), positive("thickness", thickness)
    n = count("n", n, 2)
    m = count("rings", rings)
    b = positive("ring_width", ring_width)
    if kind == "semicircular":
        ri, zc, phi0 = s / 2, 0.0, 0.0
    else:
        f = s / 4 if rise is None else positive("rise", rise)
        if f >= s / 2:
            raise SceneError(f"rise: a segmental vault needs rise < span/2 = {s / 2:g} m, got {f!r}")
        ri = (s * s / 4 + f * f) / (2 * f)
        zc = f - ri
        phi0 = math.asin(-zc / ri)
    re = ri + t

    def point(r, p):
        return [r * math.cos(p), zc + r * math.sin(p)]

    d = (math.pi - 2 * phi0) / n
    ext = point(re, phi0)
    aw = ext[0] - s / 2 if abutment_width is None else positive("abutment_width", abutment_width)
    if s / 2 + aw < ext[0] - 1e-12:
        raise SceneError(f"abutment_width: the springing joint needs at least {ext[0] - s / 2:.4g} m, got {aw:g}")
    Y = m * b
    blocks = []
    for side, label in ((1, "right"), (-1, "left")):
        I, E = point(ri, phi0), ext
        pts = [[s / 2, -0.2 * s], [s / 2 + aw, -0.2 * s], [s / 2 + aw, E[1]], E, I]
        if E[1] - I[1] < 1e-12:
            pts = [pts[0], pts[1], [s / 2 + aw, 0.0], [s / 2, 0.0]]
        pts = [[side * x, z] for x, z in pts]
        if side < 0:
            pts = pts[::-1]
        blocks.append(outline_block(f"abutment-{label}", pts, 3, 0.0, Y, fixed=True, tags=["abutment"]))
    for j in range(m):
        if stagger and j % 2:
            angles = [phi0] + [phi0 + (k + 0.5) * d for k in range(n)] + [math.pi - phi0]
        else:
            angles = [phi0 + k * d for k in range(n + 1)]
        nk = len(angles) - 1
        key = {nk // 2} if nk % 2 else {nk // 2 - 1, nk // 2}
        for k in range(nk):
            a0, a1 = angles[k], angles[k + 1]
            quad = [point(ri, a0), point(re, a0), point(re, a1), point(ri, a1)]
            tags = ["voussoir", f"ring-{j}"] + (["springing"] if k in (0, nk - 1) else []) + \
                (["key"] if k in key else [])
            blocks.append(outline_block(f"r{j}-{k}", quad, 3, j * b, (j + 1) * b, tags=tags))
    sc = B.scene(name or f"barrel-vault-{kind}-{m}x{n}-3d", 3, blocks, friction=float(mu),
                 density=float(density), sliding_faces=None)
    return finish(sc, f"{kind.capitalize()} barrel vault, {m} rings of {n} voussoirs", params)


# ----------------------------------------------------------------------------
# Cross vault

_ROT = [np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]]), np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
        np.array([[-1, 0, 0], [0, -1, 0], [0, 0, 1]]), np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]])]
_WEBS = ("east", "north", "west", "south")


def web_band_halfspaces(ri, re, ta, tb):
    """Half-spaces A p <= b of the band between radial planes at ta < tb (angles in the (y, z)
    plane from +y) of the web along +x (x >= |y|), flat intrados and extrados chords."""
    mid, c = (ta + tb) / 2, math.cos((tb - ta) / 2)
    A = [[0, math.sin(ta), -math.cos(ta)], [0, -math.sin(tb), math.cos(tb)],
         [0, -math.cos(mid), -math.sin(mid)], [0, math.cos(mid), math.sin(mid)], [-1, 1, 0], [-1, -1, 0]]
    b = [0, 0, -ri * c, re * c, 0, 0]
    return A, b


def cross_vault(span=2.0, thickness=0.2, n=8, segments=3, stagger=True, compound_groins=False, mu=0.8,
                density=2000.0, name=None) -> dict:
    """A cross (groin) vault over a square bay, on four corner piers; returns a ``blockscene/1`` dict.

    Two semicircular barrel vaults of intrados radius span/2 cross at right angles.
    Each of the four webs (east, north, west, south: the parts of the barrel along x with x >= |y|,
    and their quarter turns about z) is n voussoir courses (bands between radial planes through its
    axis, n even), each cut across its axis into ``segments`` blocks; the webs meet on the vertical
    diagonal planes x = +-y (the groins), where a course of one web and the mirrored course of the
    next share their faces. The vault's plan is the square |x|, |y| <= span/2 + thickness.
    The fixed piers are the corner squares under the springings.
    span: clear span of the four face arches (m).
    thickness: of the webs (m).
    n: courses per barrel (even).
    segments: blocks per course along the web's axis.
    stagger: odd courses are cut half a segment further along.
    compound_groins: each pair of blocks that meet on a groin plane (segment 0 of course k of one
        web and of course n-1-k of the next) becomes one compound block 'groin-{web}-{k}' whose two
        convex parts move together: a groin voussoir, L-shaped in plan, bonding the webs.
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: '{web}-{k}-{j}' (course k from the springing on the web's right, segment j from the
    groin), tagged 'voussoir', 'web-{web}', 'course-{k}', 'springing' (k = 0, n - 1), 'groin'
    (the blocks on the diagonal planes) and 'key' (the crown courses); fixed piers 'pier-{1..4}'.
    Loads: self weight (dead), 1 g along +x (live).
    """
    params = dict(span=span, thickness=thickness, n=n, segments=segments, stagger=stagger,
                  compound_groins=compound_groins, mu=mu, density=density)
    s, t = positive("span", span), positive("thickness", thickness)
    n = count("n", n, 2)
    if n % 2:
        raise SceneError(f"n: a cross vault needs an even number of courses per barrel (a crown joint), got {n}")
    nseg = count("segments", segments)
    ri, re = s / 2, s / 2 + t
    X = re
    step = X / nseg
    d = math.pi / n
    blocks = []
    for q, (px, py) in enumerate(((1, 1), (-1, 1), (-1, -1), (1, -1))):
        lo = np.array([ri if px > 0 else -re, ri if py > 0 else -re, -0.2 * s])
        hi = np.array([re if px > 0 else -ri, re if py > 0 else -ri, 0.0])
        blocks.append(box3(f"pier-{q + 1}", lo, hi, fixed=True, tags=["pier"]))
    for w, R in enumerate(_ROT):
        for k in range(n):
            ta, tb = k * d, (k + 1) * d
            A, b = web_band_halfspaces(ri, re, ta, tb)
            ys = [r * math.cos(a) for r in (ri, re) for a in (ta, tb)]
            ymin = min(abs(y) for y in ys)  # the band's nearest point to the axis plane y = 0 (n even)
            shift = step / 2 if (stagger and k % 2) else 0.0
            cuts = [shift + j * step for j in range(1, nseg + 1)]
            cuts = [c for c in cuts if ymin + 0.25 * step < c < X - 0.25 * step]
            edges = [None] + cuts + [X]
            for j in range(len(edges) - 1):
                AA, bb = list(A), list(b)
                AA.append([1, 0, 0])
                bb.append(edges[j + 1])
                if edges[j] is not None:
                    AA.append([-1, 0, 0])
                    bb.append(-edges[j])
                V = _band_vertices(AA, bb) @ R.T
                tags = ["voussoir", f"web-{_WEBS[w]}", f"course-{k}"] + \
                    (["springing"] if k in (0, n - 1) else []) + (["groin"] if j == 0 else []) + \
                    (["key"] if k in (n // 2 - 1, n // 2) else [])
                blocks.append(B.vertex_block(f"{_WEBS[w]}-{k}-{j}", V, tags=tags))
    if compound_groins:
        blocks = _groin_compounds(blocks, n)
    sc = B.scene(name or f"cross-vault-{n}x{nseg}-3d", 3, blocks, friction=float(mu), density=float(density),
                 sliding_faces=None)
    return finish(sc, f"Cross vault, {n} courses per barrel", params)


def _groin_compounds(blocks, n):
    """Merge segment 0 of course k < n/2 of each web with segment 0 of course n-1-k of the next web
    (counter-clockwise), the block across its groin plane, into one compound block."""
    by_id = {b["id"]: b for b in blocks}
    out = [b for b in blocks if b.get("fixed")]
    merged = set()
    for w in range(4):
        for k in range(n // 2):
            a, b = by_id[f"{_WEBS[w]}-{k}-0"], by_id[f"{_WEBS[(w + 1) % 4]}-{n - 1 - k}-0"]
            merged |= {a["id"], b["id"]}
            tags = list(dict.fromkeys(a["tags"] + b["tags"]))
            parts = [{"vertices": a["vertices"]}, {"vertices": b["vertices"]}]
            out.append({"id": f"groin-{_WEBS[w]}-{k}", "parts": parts, "tags": tags})
    return out + [b for b in blocks if not b.get("fixed") and b["id"] not in merged]


def _band_vertices(A, b):
    """Vertices of {p : A p <= b}, its interior point found by the Chebyshev centre LP."""
    from scipy.optimize import linprog

    A, b = np.asarray(A, float), np.asarray(b, float)
    norms = np.linalg.norm(A, axis=1)
    res = linprog([0, 0, 0, -1], A_ub=np.column_stack([A, norms]), b_ub=b,
                  bounds=[(None, None)] * 3 + [(0, None)], method="highs")
    if res.status != 0 or res.x[3] <= 0:
        raise SceneError("cross vault: a voussoir has no volume (raise segments or thickness)")
    return halfspace_vertices(A, b, res.x[:3])
