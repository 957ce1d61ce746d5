"""A scene's declared mirror symmetry, checked (scene key ``"symmetry": "mirror"``).

The mirror plane is vertical (it contains gravity), contains the live load's horizontal
direction h (:func:`limit.verdict.kinematic_check.horizontal_direction`) and passes through the
volume centroid c of the free blocks. Its unit normal is n = up x h, and a point p
mirrors to p - 2 ((p - c) . n) n. The scene is symmetric when every block's mirrored
centroid is the centroid of a block of the same volume (relative 1e-6) and the same
fixity whose corners are its mirrored corners, within ``TOL`` x the scene's size (free
blocks), and every contact's mirrored centroid is that of a contact of the same area (so a
support counts by its contacts, not by its extent). Then alpha(theta) = alpha(-theta) for the live
load turned by theta about the vertical (:mod:`limit.direction_sweep`).
"""
from __future__ import annotations

import numpy as np

from limit.model.reversal_mirror import TOL, reflect, same_shape


def mirror_plane(scene) -> tuple[np.ndarray, np.ndarray]:
    """(point c (3,), unit normal n (3,)) of the mirror plane of a 3D scene."""
    from limit.verdict.kinematic_check import horizontal_direction

    if scene.dim != 3:
        raise ValueError("symmetry: a mirror plane is declared for 3D scenes only")
    g = np.asarray(scene.gravity, dtype=float)
    up = -g / np.linalg.norm(g)
    n = np.cross(up, horizontal_direction(scene))
    free = [b for b in scene.blocks if not b.fixed] or list(scene.blocks)
    vol = np.array([b.volume for b in free])
    c = (vol[:, None] * np.array([b.centroid for b in free])).sum(0) / vol.sum()
    return c, n / np.linalg.norm(n)


def check_mirror(scene) -> None:
    """Raise ValueError naming the block farthest from having a mirror partner (module docstring)."""
    c, n = mirror_plane(scene)
    cen = np.array([b.centroid for b in scene.blocks], dtype=float)
    vol = np.array([b.volume for b in scene.blocks], dtype=float)
    fixed = np.array([b.fixed for b in scene.blocks])
    size = float(np.linalg.norm(np.ptp(cen, axis=0))) or 1.0
    mirrored = reflect(cen, c, n)
    tol = TOL * size

    free = [i for i, b in enumerate(scene.blocks) if not b.fixed]  # supports count by their contacts (below)
    miss = {}
    for i in free:
        dist = np.linalg.norm(cen - mirrored[i], axis=1)
        like = (np.abs(vol - vol[i]) <= 1e-6 * vol[i]) & ~fixed
        ok = np.flatnonzero(like & (dist <= tol))
        if not any(same_shape(scene.blocks, i, int(j), c, n, tol) for j in ok):
            miss[i] = float(dist[like].min(initial=np.inf))
    if miss:  # the worst first: a moved block also moves the plane a little for all others
        i = max(miss, key=miss.get)
        raise ValueError(f"symmetry: block '{scene.blocks[i].id}' has no mirror image about the vertical plane of "
                         f"the live load through ({', '.join(f'{x:.4g}' for x in c)}) m (the nearest block of its "
                         f"volume to its image is {miss[i]:.3g} m away)")
    from limit.geom.interfaces import find_interfaces

    I = find_interfaces(scene)
    ic = np.asarray(I.centroid, float)
    im = reflect(ic, c, n)
    area = np.asarray(I.area, float)
    for k in range(len(I)):
        dist = np.linalg.norm(ic - im[k], axis=1)
        if not np.any((dist <= tol) & (np.abs(area - area[k]) <= 1e-6 * area[k])):
            a, b = scene.blocks[int(I.a[k])].id, scene.blocks[int(I.b[k])].id
            raise ValueError(f"symmetry: the contact {a}|{b} has no mirror image about the vertical plane of the "
                             f"live load through ({', '.join(f'{x:.4g}' for x in c)}) m")
