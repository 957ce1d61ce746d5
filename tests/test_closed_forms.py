"""scenes/closed_forms.arch_hinge_alpha (the arch reference of the catalog) against a second
four-hinge search written here: the mechanism from the null space of the hinge constraints
(numpy SVD) instead of instantaneous centres. Lengths in m, weights in N (per unit depth)."""
import itertools
import json
import math

import numpy as np
import pytest

from scenes.catalog import CATALOG_DIR
from scenes.closed_forms import arch_hinge_alpha, arch_reference


def four_hinge_nullspace(J, C, W, live=(1.0, 0.0), gravity=(0.0, -1.0)):
    """Least alpha = -(dead-load work) / (live-load work) over four-hinge mechanisms.

    For hinges at joints a < b < c < d (either end of each), the bodies a..b-1, b..c-1, c..d-1
    have velocities (u, v, w) each (9 unknowns); the body velocities agree at each hinge (the
    supports at rest): 8 equations, whose null space (SVD, rank 8 required) is the mechanism, up
    to sign. Admissible if at the other end of every hinged joint the side of higher index moves
    away from the side of lower index (the normal oriented from voussoir joint-1 to voussoir joint)
    at all four joints in the same sense. Returns (alpha, hinges)."""
    J, C, W = (np.asarray(a, float) for a in (J, C, W))
    q, g = np.asarray(live, float), np.asarray(gravity, float)
    n = len(C)
    size = float(np.ptp(J.reshape(-1, 2), axis=0).max())

    def rows(body, p, sign):
        r = np.zeros((2, 9))
        r[:, 3 * body:3 * body + 2] = sign * np.eye(2)
        r[:, 3 * body + 2] = sign * np.array([-p[1], p[0]])
        return r

    def normal(j):
        t = J[j, 1] - J[j, 0]
        nrm = np.array([t[1], -t[0]]) / np.linalg.norm(t)
        mid = J[j].mean(axis=0)
        high = C[j] if j < n else 2 * mid - C[n - 1]
        return nrm if (high - mid) @ nrm > 0 else -nrm

    best = (math.inf, None)
    for hinge_joints in itertools.combinations(range(n + 1), 4):
        bounds = list(hinge_joints)
        for ends in itertools.product((0, 1), repeat=4):
            H = [J[j, e] for j, e in zip(bounds, ends)]
            A = np.vstack([rows(0, H[0], 1), rows(0, H[1], 1) + rows(1, H[1], -1),
                           rows(1, H[2], 1) + rows(2, H[2], -1), rows(2, H[3], 1)])
            _, s, Vt = np.linalg.svd(A)
            if s[-1] < 1e-9 * s[0]:
                continue  # rank < 8: not a single-degree-of-freedom mechanism
            x = Vt[-1]

            def body_of(k):
                for i in range(3):
                    if bounds[i] <= k < bounds[i + 1]:
                        return i
                return None  # a support side, at rest

            def vel(k, p):
                i = body_of(k)
                if i is None:
                    return np.zeros(2)
                u, v, w = x[3 * i:3 * i + 3]
                return np.array([u - w * p[1], v + w * p[0]])

            opening = np.array([(vel(j, J[j, 1 - e]) - vel(j - 1, J[j, 1 - e])) @ normal(j)
                                for j, e in zip(bounds, ends)])
            scale = max(np.abs(x).max() * size, 1e-300)
            if np.all(opening >= -1e-9 * scale):
                sense = 1.0
            elif np.all(opening <= 1e-9 * scale):
                sense = -1.0
            else:
                continue
            vc = np.array([vel(k, C[k]) for k in range(n)])
            w_live, w_dead = sense * float(W @ (vc @ q)), sense * float(W @ (vc @ g))
            if w_live > 1e-12 * scale * W.sum():
                alpha = -w_dead / w_live
                if -1e-12 <= alpha < best[0]:
                    best = (alpha, list(zip(bounds, ends)))
    return best


def arch_geometry(n, R, t, span_deg):
    """Joints (radial, intrados end first), shoelace centroids and areas of n equal voussoirs of a
    circular arch of mean radius R, thickness t, embracing span_deg, symmetric about x = 0."""
    ri, re = R - t / 2, R + t / 2
    phis = np.linspace(math.radians(90 - span_deg / 2), math.radians(90 + span_deg / 2), n + 1)
    J = np.array([[[ri * math.cos(p), ri * math.sin(p)], [re * math.cos(p), re * math.sin(p)]] for p in phis])
    C, W = [], []
    for k in range(n):
        P = np.array([J[k, 0], J[k, 1], J[k + 1, 1], J[k + 1, 0]])
        x, y = P[:, 0], P[:, 1]
        xn, yn = np.roll(x, -1), np.roll(y, -1)
        cr = x * yn - xn * y
        A = cr.sum() / 2
        C.append([((x + xn) * cr).sum() / (6 * A), ((y + yn) * cr).sum() / (6 * A)])
        W.append(abs(A))
    return J, np.array(C), np.array(W)


# the two 9-voussoir cases take about 5-9 s each (the null-space search over 210 hinge sets)
@pytest.mark.parametrize("n, R, t, span", [(3, 1.0, 0.3, 180.0), (5, 1.0, 0.15, 180.0), (7, 1.5, 0.2, 120.0),
                                           pytest.param(9, 1.0, 0.15, 180.0, marks=pytest.mark.slow),
                                           pytest.param(9, 1.0, 0.25, 150.0, marks=pytest.mark.slow),
                                           (6, 2.0, 0.18, 160.0)])
def test_arch_hinge_alpha_matches_nullspace_search(n, R, t, span):
    """Same least alpha (rel 1e-9) and same hinges from both searches, on arches of 3 to 9 voussoirs."""
    J, C, W = arch_geometry(n, R, t, span)
    ref = arch_hinge_alpha(J, C, W)
    alpha, hinges = four_hinge_nullspace(J, C, W)
    assert math.isfinite(alpha) and alpha > 0
    assert ref["alpha"] == pytest.approx(alpha, rel=1e-9)
    assert [tuple(h) for h in ref["hinges"]] == [tuple(h) for h in hinges]
    assert arch_reference(n, R, t, span) == pytest.approx(alpha, rel=1e-9)


@pytest.mark.parametrize("name, n, R, t, span", [  # the 9-voussoir search: about 2 s
    pytest.param("arch-semicircular-9-2d", 9, 1.0, 0.15, 180.0, marks=pytest.mark.slow),
    ("arch-segmental-7-3d", 7, 1.5, 0.2, 120.0)])
def test_catalog_arch_reference(name, n, R, t, span):
    """The catalog's expected alpha of its two small arches (from arch_reference, rounded to 1e-10)
    equals the null-space search on the same geometry (builders.arch: R = 1.0, t = 0.15, 180 deg;
    R = 1.5, t = 0.2, 120 deg)."""
    d = json.loads((CATALOG_DIR / f"{name}.json").read_text())
    alpha, _ = four_hinge_nullspace(*arch_geometry(n, R, t, span))
    assert d["expected"]["alpha"] == pytest.approx(alpha, abs=1e-9)


def portal_frame(b=0.3, h=1.5, span=1.0, d=0.3):
    """portal-2d as three 'voussoirs': columns b x h at x in [0, b] and [b + span, 2 b + span], a
    lintel 2 b + span long and d deep on top; joints: left base, left top, right top, right base."""
    L = 2 * b + span
    J = np.array([[[0, 0], [b, 0]], [[0, h], [b, h]], [[L - b, h], [L, h]], [[L - b, 0], [L, 0]]], float)
    C = np.array([[b / 2, h / 2], [L / 2, h + d / 2], [L - b / 2, h / 2]])
    return J, C, np.array([b * h, L * d, b * h])


def test_nullspace_search_on_the_portal_by_hand():
    """Sway of portal-2d: both columns turn about their right toes, the lintel translates by
    (h, b) per unit rotation. Work against the dead load (2 W_c b / 2 + W_l b), live-load work
    (2 W_c h / 2 + W_l h): alpha = b / h = 0.3 / 1.5 = 0.2 (the catalog's analytic portal-2d value)."""
    alpha, hinges = four_hinge_nullspace(*portal_frame())
    assert alpha == pytest.approx(0.2, rel=1e-9)
    assert hinges == [(0, 1), (1, 0), (2, 0), (3, 1)]


@pytest.mark.xfail(strict=True, reason="arch_hinge_alpha builds the middle body's rotation centre from the "
                   "lines h1-h2 and h3-h4 and skips them when parallel: a translating middle body (portal "
                   "sway) is never tried; measured: alpha inf, 0 mechanisms")
def test_arch_hinge_alpha_translating_middle_body():
    """The same portal through arch_hinge_alpha: b / h = 0.2 expected (see the test above)."""
    assert arch_hinge_alpha(*portal_frame())["alpha"] == pytest.approx(0.2, rel=1e-9)
