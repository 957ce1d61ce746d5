"""Dead and live load vectors on the free blocks' degrees of freedom.

Each free block has ``ndof`` generalised forces at its centroid, in the global
axes: 2D ``[Fx, Fy, Mz]``, 3D ``[Fx, Fy, Fz, Mx, My, Mz]`` (N and N m, moments
about the block centroid, counter-clockwise / right-handed positive). Loads on
fixed blocks have no effect and are dropped. Pressure loads: :mod:`limit.model.pressure`.
"""
from __future__ import annotations

import numpy as np


def free_index(scene) -> np.ndarray:
    """(n_blocks,) position of each block among the free blocks, -1 for fixed ones."""
    idx = -np.ones(scene.n_blocks, dtype=int)
    free = scene.free
    idx[free] = np.arange(len(free))
    return idx


def _cross(dim, r, f):
    if dim == 2:
        return np.array([r[0] * f[1] - r[1] * f[0]])
    return np.cross(r, f)


def assemble(scene, loads) -> np.ndarray:
    """Generalised force array (n_free, ndof) of a resolved load list (``scene.dead`` or ``scene.live``)."""
    dim = scene.dim
    fi = free_index(scene)
    out = np.zeros((len(scene.free), scene.ndof))
    g = scene.gravity
    gnorm = float(np.linalg.norm(g))
    mass = np.array([b.mass for b in scene.blocks])
    for ld in loads:
        sel = np.array([i for i in ld["_blocks"] if fi[i] >= 0], dtype=int)
        if not sel.size:
            continue
        t = ld["type"]
        if t == "self_weight":
            out[fi[sel], :dim] += mass[sel, None] * g
        elif t == "body_force":
            out[fi[sel], :dim] += mass[sel, None] * gnorm * np.asarray(ld["direction"], dtype=float)
        elif t == "point_force":
            i = int(sel[0])
            f = np.asarray(ld["force"], dtype=float)
            c = scene.blocks[i].centroid
            p = np.asarray(ld.get("point", c), dtype=float)
            out[fi[i], :dim] += f
            out[fi[i], dim:] += _cross(dim, p - c, f)
        elif t == "pressure":
            from limit.model.pressure import resultant

            up = -g / gnorm
            for i in sel:
                F, M = resultant(scene.blocks[i], ld, up, scene.thickness)
                out[fi[i], :dim] += F
                out[fi[i], dim:] += M
    return out


def dead_and_live(scene) -> tuple[np.ndarray, np.ndarray]:
    """(f0, fL): the dead and live generalised forces, each (n_free, ndof)."""
    return assemble(scene, scene.dead), assemble(scene, scene.live)


def horizontal_direction(scene) -> np.ndarray:
    """Unit vector (d,) of the live load's resultant force with its component along gravity
    removed; raises ValueError when the live load has no horizontal resultant."""
    _, fL = dead_and_live(scene)
    F = fL[:, :scene.dim].sum(axis=0)
    g = np.asarray(scene.gravity, dtype=float)
    down = g / np.linalg.norm(g)
    h = F - (F @ down) * down
    n = float(np.linalg.norm(h))
    if n <= 1e-12 * max(float(np.linalg.norm(F)), 1e-300):
        raise ValueError("the live load has no horizontal resultant: no seismic direction to check")
    return h / n
