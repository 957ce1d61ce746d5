"""Scaling of the interface actions: an estimate of each interface's force.

Interior-point tolerances are absolute on the scaled problem, so when the
interface forces span orders of magnitude (the bed joints at the foot of a
100-course wall carry 100 times those at the top) a uniform force unit leaves
the small ones poorly resolved and alpha off by 1e-3 at 10,000 blocks (see
bench/lp_bench.py). Each interface is therefore scaled by an estimate of its
normal force, from a load path computed top-down: every free block passes the
load it carries (its own dead and live forces plus what rests on it) to the
interfaces it rests on, in proportion to their area times the cosine between
their normal and the vertical, and through them to the blocks below. Joints
that carry little vertically (head joints) get a floor of a quarter of the
load the lighter of their two blocks carries.
"""
from __future__ import annotations

import numpy as np


def normal_force_estimate(scene, I, f0, fL) -> np.ndarray:
    """(m,) estimated normal force magnitude of each interface, N (> 0)."""
    d = scene.dim
    m = len(I)
    free = scene.free
    nb = scene.n_blocks
    up = -scene.gravity / np.linalg.norm(scene.gravity)
    F0 = np.asarray(f0).reshape(len(free), -1)[:, :d]
    FL = np.asarray(fL).reshape(len(free), -1)[:, :d]
    load = np.zeros(nb)
    load[free] = np.linalg.norm(F0, axis=1) + np.linalg.norm(FL, axis=1)
    if m == 0:
        return np.zeros(0)
    c = I.normal @ up
    upper = np.where(c > 0, I.b, I.a)   # the block resting on the interface
    lower = np.where(c > 0, I.a, I.b)
    cc = np.abs(c)
    w = I.area * cc
    supports = cc > 1e-3
    fixed = np.array([b.fixed for b in scene.blocks])
    height = np.array([b.centroid @ up for b in scene.blocks])

    # Interfaces grouped by the block resting on them.
    ks = np.flatnonzero(supports)
    order = np.argsort(upper[ks], kind="stable")
    ks = ks[order]
    ptr = np.searchsorted(upper[ks], np.arange(nb + 1))
    carried = load.copy()
    est = np.zeros(m)
    w_l, lower_l, cc_l = w.tolist(), lower.tolist(), np.maximum(cc, 0.2).tolist()
    ks_l, ptr_l = ks.tolist(), ptr.tolist()
    for i in np.argsort(-height, kind="stable").tolist():
        if fixed[i]:
            continue
        group = ks_l[ptr_l[i]:ptr_l[i + 1]]
        if not group:
            continue
        total = sum(w_l[k] for k in group)
        ci = carried[i]
        for k in group:
            share = ci * w_l[k] / total
            est[k] += share / cc_l[k]
            j = lower_l[k]
            if not fixed[j]:
                carried[j] += share
    # Joints that carry little vertically still see the horizontal actions of the blocks they
    # separate, which scale with what those blocks carry: the lighter of the two (a pebble
    # beside a wall must not be scaled like the wall).
    ca = np.where(fixed[I.a], np.inf, carried[I.a])
    cb = np.where(fixed[I.b], np.inf, carried[I.b])
    floor = 0.25 * np.minimum(ca, cb)
    floor = np.where(np.isfinite(floor), floor, 0.0)
    est = np.maximum(est, floor)
    tiny = 1e-12 * max(float(load.max()), 1e-300)
    return np.maximum(est, tiny)
