"""The constants that depend on the dimension, in one place.

A free block's generalised velocity (or displacement) at its centroid is
``[ux, uy, rz]`` in 2D and ``[ux, uy, uz, rx, ry, rz]`` in 3D (m, rad; global axes,
right-handed, rotations counter-clockwise about +z in 2D). An interface carries the
generalised stresses ``(V, N, M)`` in 2D and ``(V1, V2, N, M1, M2, T)`` in 3D (N, N m,
in the interface frame: N is the normal force, positive in compression, V the shears, M
the bending moments, T the torsion).
"""
from __future__ import annotations

import numpy as np

DOF_NAMES = {2: ("ux", "uy", "rz"), 3: ("ux", "uy", "uz", "rx", "ry", "rz")}
STRESS_NAMES = {2: ("V", "N", "M"), 3: ("V1", "V2", "N", "M1", "M2", "T")}


def ndof(dim: int) -> int:
    """Generalised dofs per block and stress components per interface: 3 in 2D, 6 in 3D."""
    return len(DOF_NAMES[dim])


def normal_index(dim: int) -> int:
    """Position of N among the interface stresses: 1 in 2D, 2 in 3D."""
    return STRESS_NAMES[dim].index("N")


def first_moment_index(dim: int) -> int:
    """Position of the first moment (M in 2D, M1 in 3D): the stresses from it on are moments."""
    return STRESS_NAMES[dim].index("M" if dim == 2 else "M1")


def rigid_velocity(m, r, dim: int) -> np.ndarray:
    """Velocity of points of a rigid block (m/s, or m for a displacement), shape of ``r``.

    ``m`` is the block's generalised velocity at its centroid (``ndof(dim)``,), ``r`` the
    points' offsets from the centroid, (n, dim) or (dim,). v = u + w x r; in 2D
    w x r = rz (-r_y, r_x).
    """
    m = np.asarray(m, dtype=float)
    r = np.asarray(r, dtype=float)
    if dim == 2:
        return m[:2] + m[2] * np.stack([-r[..., 1], r[..., 0]], axis=-1)
    return m[:3] + np.cross(m[3:6], r)
