"""Rejection of overlapping blocks.

Two convex blocks are disjoint or merely touching when a face plane of one
leaves every vertex of the other outside (separating-axis test on face
normals, exact in 2D). In 3D a pair that no face plane separates (possible for
edge-to-edge crossings) is settled by a small LP: the largest ball common to
both blocks; its radius is the overlap depth.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import linprog

from limit.geom import _broadphase as broadphase, _facetable as facetable
from limit.geom.interfaces import pieces
from limit.errors import SceneError


def separation(ft: facetable.FaceTable, a: np.ndarray, b: np.ndarray, chunk: int = 100_000) -> np.ndarray:
    """Signed separation (m) of each pair along the best face normal of either block.

    Positive: a gap; zero: touching; negative: no face plane separates them and
    the value is minus the smallest penetration along a face normal.
    """
    out = np.empty(len(a))
    for s in range(0, len(a), chunk):
        ia, ib = a[s:s + chunk], b[s:s + chunk]
        # Coordinates relative to the block owning the faces keep the test accurate far from the origin.
        sab = (np.einsum("pfd,pvd->pfv", ft.block_normals[ia], ft.block_verts[ib] - ft.block_centre[ia][:, None])
               - ft.block_offsets[ia][:, :, None]).min(axis=2).max(axis=1)
        sba = (np.einsum("pfd,pvd->pfv", ft.block_normals[ib], ft.block_verts[ia] - ft.block_centre[ib][:, None])
               - ft.block_offsets[ib][:, :, None]).min(axis=2).max(axis=1)
        out[s:s + chunk] = np.maximum(sab, sba)
    return out


def common_depth(ft: facetable.FaceTable, i: int, j: int) -> float:
    """Radius (m) of the largest ball inside both blocks i and j (0 if none)."""
    c = ft.block_centre[i]
    A = np.vstack([ft.block_normals[i], ft.block_normals[j]])
    b = np.concatenate([ft.block_offsets[i],
                        ft.block_offsets[j] + ft.block_normals[j] @ (ft.block_centre[j] - c)])
    d = A.shape[1]
    # maximise t subject to A x + t <= b (rows have unit normals), t >= 0
    res = linprog(np.r_[np.zeros(d), -1.0], A_ub=np.hstack([A, np.ones((len(A), 1))]), b_ub=b,
                  bounds=[(None, None)] * d + [(0, None)], method="highs")
    return float(res.x[-1]) if res.status == 0 else 0.0


def _piece_name(blocks, owner, first, k) -> str:
    b = blocks[owner[k]]
    return f"'{b.id}'" + (f" (part {k - first[owner[k]]})" if b.parts else "")


def check_overlaps(scene) -> None:
    """Raise SceneError naming the first pair of blocks (or parts of compound blocks) that overlap
    beyond the tolerance. The parts of one compound block must not overlap either."""
    blocks = scene.blocks
    polys, owner = pieces(blocks)
    if len(polys) < 2:
        return
    first = np.searchsorted(owner, np.arange(len(blocks)))
    tol = scene.tolerance
    ft = facetable.build(polys)
    lo, hi = broadphase.aabbs(polys)
    a, b = broadphase.candidate_pairs(lo, hi, -tol)
    if not len(a):
        return
    sep = separation(ft, a, b)
    suspect = np.flatnonzero(sep < -tol)
    for k in suspect[np.argsort(sep[suspect])]:
        i, j = int(a[k]), int(b[k])
        depth = -sep[k] if scene.dim == 2 else common_depth(ft, i, j)
        if depth > tol:
            raise SceneError(
                f"blocks {_piece_name(blocks, owner, first, i)} and {_piece_name(blocks, owner, first, j)} overlap "
                f"(penetration {depth:.3g} m, tolerance {tol:.3g} m)"
            )
