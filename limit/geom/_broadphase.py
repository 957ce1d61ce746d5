"""Broad phase: pairs of blocks whose bounding boxes touch, by sweep and prune.

The sweep runs along the axis that yields the fewest candidate pairs, so a wall
of n blocks costs about O(n log n) plus the number of neighbouring pairs.
Everything is vectorised with numpy.
"""
from __future__ import annotations

import numpy as np


def aabbs(polys) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corners (n, d) of the polytopes' axis-aligned bounding boxes."""
    lo = np.array([p.vertices.min(axis=0) for p in polys])
    hi = np.array([p.vertices.max(axis=0) for p in polys])
    return lo, hi


def candidate_pairs(lo: np.ndarray, hi: np.ndarray, tol: float, chunk: int = 2_000_000):
    """Index pairs (i, j), i < j, whose boxes overlap or touch within ``tol``.

    lo, hi : (n, d) box corners. Returns two int arrays of equal length.
    """
    n, d = lo.shape
    if n < 2:
        return np.empty(0, int), np.empty(0, int)
    best = None
    for axis in range(d):
        order = np.argsort(lo[:, axis], kind="stable")
        los = lo[order, axis]
        end = np.searchsorted(los, hi[order, axis] + tol, side="right")
        count = np.maximum(end - np.arange(1, n + 1), 0)
        total = int(count.sum())
        if best is None or total < best[0]:
            best = (total, axis, order, count)
    _, axis, order, count = best
    others = [a for a in range(d) if a != axis]

    out_i, out_j = [], []
    starts = np.cumsum(count) - count
    # Process sweep positions in chunks so memory stays bounded.
    k0 = 0
    while k0 < n:
        k1 = k0
        acc = 0
        while k1 < n and (acc + count[k1] <= chunk or k1 == k0):
            acc += count[k1]
            k1 += 1
        ks = np.arange(k0, k1)
        c = count[ks]
        if c.sum():
            rep = np.repeat(ks, c)
            offs = np.arange(c.sum()) - np.repeat(starts[ks] - starts[k0], c)
            pi = order[rep]
            pj = order[rep + 1 + offs]
            keep = np.ones(len(pi), bool)
            for a in others:
                keep &= (lo[pj, a] <= hi[pi, a] + tol) & (lo[pi, a] <= hi[pj, a] + tol)
            pi, pj = pi[keep], pj[keep]
            out_i.append(np.minimum(pi, pj))
            out_j.append(np.maximum(pi, pj))
        k0 = k1
    if not out_i:
        return np.empty(0, int), np.empty(0, int)
    return np.concatenate(out_i), np.concatenate(out_j)
