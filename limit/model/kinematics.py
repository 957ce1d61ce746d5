"""Compatibility matrix B: block velocities -> interface relative motions.

Unknowns: for each free block, ``ndof`` generalised velocities at its centroid
in the global axes, 2D ``[ux, uy, rz]``, 3D ``[ux, uy, uz, rx, ry, rz]``
(translations m/s-like, rotations rad/s-like; only ratios matter). Fixed blocks
carry no unknowns. Column ``f * ndof + j`` is dof j of the f-th free block
(``loads.free_index``).

Interface generalised strains, in the interface's local frame, of block b
relative to block a at the contact centroid p:
2D ``q = [t.dv, n.dv, dw]`` and 3D ``q = [t1.dv, t2.dv, n.dv, t1.dw, t2.dw, n.dw]``
with ``dv = v_b(p) - v_a(p)``, ``dw = w_b - w_a``. Row ``k * nq + i``.

The conjugate generalised stresses r are the force and moment (about p) that
block a exerts on block b, in the same local frame: 2D ``[V, N, M]``, 3D
``[V1, V2, N, M1, M2, T]``; N > 0 is compression. Then the power of the
contact actions on the blocks is r . q, and equilibrium of the blocks reads
``B.T @ r + f0 + alpha * fL = 0``.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from limit.model.loads import free_index


def _skew(r):
    """(m, 3, 3) matrices S with S @ w = r x w."""
    z = np.zeros(len(r))
    return np.stack([np.stack([z, -r[:, 2], r[:, 1]], -1),
                     np.stack([r[:, 2], z, -r[:, 0]], -1),
                     np.stack([-r[:, 1], r[:, 0], z], -1)], -2)


def local_frames(I) -> np.ndarray:
    """(m, d, d) rotation matrices whose rows are the local axes (2D: t, n; 3D: t1, t2, n)."""
    if I.dim == 2:
        return np.stack([I.t1, I.normal], axis=1)
    return np.stack([I.t1, I.t2, I.normal], axis=1)


def block_terms(scene, I, side: str) -> np.ndarray:
    """(m, nq, ndof) contribution of block ``side`` ('a' or 'b') to q, before its sign."""
    idx = I.a if side == "a" else I.b
    c = np.array([scene.blocks[i].centroid for i in idx]) if len(idx) else np.zeros((0, scene.dim))
    r = I.centroid - c  # lever arm from the block centroid to the contact centroid
    Q = local_frames(I)
    m = len(idx)
    if scene.dim == 2:
        out = np.zeros((m, 3, 3))
        out[:, :2, :2] = Q
        # velocity of p from a rotation w about z: w * (-r_y, r_x)
        perp = np.column_stack([-r[:, 1], r[:, 0]])
        out[:, :2, 2] = np.einsum("mij,mj->mi", Q, perp)
        out[:, 2, 2] = 1.0
        return out
    out = np.zeros((m, 6, 6))
    out[:, :3, :3] = Q
    # v(p) = u + w x r = u - S(r) w
    out[:, :3, 3:] = -np.einsum("mij,mjk->mik", Q, _skew(r))
    out[:, 3:, 3:] = Q
    return out


def compatibility(scene, I) -> sp.csr_matrix:
    """Sparse B of shape (m * nq, n_free * ndof) such that q = B @ u (see module docstring)."""
    fi = free_index(scene)
    nq = ndof = scene.ndof
    m = len(I)
    rows, cols, vals = [], [], []
    k = np.arange(m)
    for side, sign in (("a", -1.0), ("b", 1.0)):
        idx = I.a if side == "a" else I.b
        f = fi[idx]
        keep = f >= 0
        T = sign * block_terms(scene, I, side)[keep]
        kk, ff = k[keep], f[keep]
        R = (kk[:, None, None] * nq + np.arange(nq)[None, :, None]) + np.zeros((1, 1, ndof), int)
        C = (ff[:, None, None] * ndof + np.arange(ndof)[None, None, :]) + np.zeros((1, nq, 1), int)
        rows.append(R.ravel())
        cols.append(C.ravel())
        vals.append(T.ravel())
    B = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(m * nq, len(scene.free) * ndof))
    B.eliminate_zeros()
    return B
