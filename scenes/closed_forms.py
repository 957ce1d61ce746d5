"""Reference values computed independently of the limit-analysis code.

:func:`arch_hinge_alpha`: the collapse factor of a 2D voussoir arch between
fixed supports by the classical mechanism method: every four-hinge mechanism
(hinges at the intrados or extrados end of any four joints, the springings
included) is built from instantaneous centres, kept if every hinged joint
opens (no interpenetration at its other end), and its load factor follows
from virtual work, alpha = -(work of the dead load) / (work of the live
load); the least over all mechanisms is the hinging collapse factor
(upper-bound theorem, sliding excluded). It uses only the voussoir geometry
and masses, none of :mod:`limit`.
"""
from __future__ import annotations

import functools
import itertools

import numpy as np

from limit.geom.geometry import polygon_area_centroid


def _rot(w, r):
    """Velocity of lever arm(s) r under a rotation w about z (2D)."""
    r = np.asarray(r, dtype=float)
    return w * np.stack([-r[..., 1], r[..., 0]], axis=-1)


def _intersect(p1, d1, p2, d2):
    A = np.column_stack([d1, -d2])
    if abs(np.linalg.det(A)) < 1e-14:
        return None
    s = np.linalg.solve(A, p2 - p1)
    return p1 + s[0] * d1


def arch_hinge_alpha(joints, centroids, weights, live_dir=(1.0, 0.0), gravity_dir=(0.0, -1.0)) -> dict:
    """Least load factor over four-hinge mechanisms of a voussoir arch.

    joints: (n + 1, 2, 2) the joints from one support to the other, each as its
    two end points (e.g. intrados, extrados); voussoir k lies between joints
    k and k + 1. centroids (n, 2), weights (n,) in N. Dead load: the weights
    along ``gravity_dir``; live load: the weights times ``live_dir``.
    Returns {"alpha", "hinges" [(joint, end) x 4], "n_mechanisms"}.
    """
    J = np.asarray(joints, dtype=float)
    C = np.asarray(centroids, dtype=float)
    W = np.asarray(weights, dtype=float)
    g = np.asarray(gravity_dir, dtype=float)
    q = np.asarray(live_dir, dtype=float)
    n = len(C)
    best = {"alpha": np.inf, "hinges": None, "n_mechanisms": 0}
    for a, b, c, d in itertools.combinations(range(n + 1), 4):
        for ea, eb, ec, ed in itertools.product((0, 1), repeat=4):
            h = [J[a, ea], J[b, eb], J[c, ec], J[d, ed]]
            # body 1 (voussoirs a..b-1) turns about h1 with unit rate, body 3 (c..d-1) about h4,
            # body 2 (b..c-1) about the intersection of lines h1-h2 and h3-h4.
            c2 = _intersect(h[0], h[1] - h[0], h[3], h[2] - h[3])
            if c2 is None:
                continue
            w1 = 1.0
            v2 = _rot(w1, h[1] - h[0])
            r = h[1] - c2
            den = r @ r
            if den < 1e-24:
                continue
            w2 = (r[0] * v2[1] - r[1] * v2[0]) / den
            v3 = _rot(w2, h[2] - c2)
            r3 = h[2] - h[3]
            w3 = (r3[0] * v3[1] - r3[1] * v3[0]) / (r3 @ r3)
            centres = [(h[0], w1), (c2, w2), (h[3], w3)]
            ranges = [(a, b), (b, c), (c, d)]

            def vel(k, p):
                for (lo, hi), (o, w) in zip(ranges, centres):
                    if lo <= k < hi:
                        return _rot(w, p - o)
                return np.zeros(2)

            # Every hinged joint must open: the relative velocity of its other end along the
            # normal pointing from the lower-index side to the higher has one sign at all four
            # hinges; that sign is the sense in which the mechanism can run.
            openings = []
            for joint, end in ((a, ea), (b, eb), (c, ec), (d, ed)):
                p_other = J[joint, 1 - end]
                tj = J[joint, 1] - J[joint, 0]
                nrm = np.array([tj[1], -tj[0]])
                mid = J[joint].mean(axis=0)
                probe = C[joint] if joint < n else 2 * mid - C[joint - 1]
                if (probe - mid) @ nrm < 0:
                    nrm = -nrm
                rel = vel(joint, p_other) - vel(joint - 1, p_other)
                openings.append(float(rel @ nrm) / max(float(np.linalg.norm(rel)), 1e-300))
            openings = np.array(openings)
            if np.all(openings >= -1e-12):
                sense = 1.0
            elif np.all(openings <= 1e-12):
                sense = -1.0
            else:
                continue
            v = np.array([vel(k, C[k]) for k in range(n)])
            live = sense * float(np.sum(W * (v @ q)))
            dead = sense * float(np.sum(W * (v @ g)))
            if live > 1e-15:
                alpha = -dead / live
                best["n_mechanisms"] += 1
                if -1e-12 <= alpha < best["alpha"]:
                    best.update(alpha=alpha, hinges=[(a, ea), (b, eb), (c, ec), (d, ed)])
    return best


@functools.lru_cache(maxsize=None)
def arch_reference(n, R, t, span_deg=180.0, live_dir=(1.0, 0.0)) -> float:
    """Hinging collapse factor of :func:`scenes.builders.arch` (2D) by the mechanism method."""
    import math

    ri, re = R - t / 2, R + t / 2
    phi0 = math.radians(90.0 - span_deg / 2)
    phis = np.linspace(phi0, math.pi - phi0, n + 1)
    joints = np.array([[[ri * math.cos(p), ri * math.sin(p)], [re * math.cos(p), re * math.sin(p)]] for p in phis])
    cents, weights = [], []
    for k in range(n):
        quad = np.array([joints[k, 0], joints[k, 1], joints[k + 1, 1], joints[k + 1, 0]])
        A, c = polygon_area_centroid(quad)
        cents.append(c)
        weights.append(abs(A))
    return arch_hinge_alpha(joints, np.array(cents), np.array(weights), live_dir)["alpha"]
