"""Host side: the plain JSON job that the YADE script reads.

Everything YADE needs is computed here with :mod:`limit` (validated scene,
loads, interfaces), so the YADE side needs no project package:

* ``blocks``: per block ``id``, ``fixed``, ``mass`` (kg) and ``vertices``
  (world coordinates, m, always 3D: a 2D polygon becomes the prism z in [0, t]).
* ``f0``, ``fL``: per free block (scene order) the dead and live generalised
  force ``[Fx, Fy, Fz, Mx, My, Mz]`` at its centroid in global axes (N, N m),
  from :func:`limit.loads.dead_and_live` (2D ``[Fx, Fy, Mz]`` padded with zeros).
* ``interfaces``: ``[i, j, area]`` (m^2, 2D: length x thickness) of every
  contact found by :func:`limit.interfaces.find_interfaces`;
  ``friction`` (default mu) and ``friction_pairs`` ``[i, j, mu]`` (overrides).
* ``rho_g`` (N/m^3): rho |g| with rho the mass-weighted mean density of the
  free blocks; the YADE side sets the volumetric normal stiffness
  kn = rho_g / eps (N/m^3) for each settlement strain eps of ``params["eps"]``.
* ``params``: the pushover knobs (dem_validation.params).
"""
from __future__ import annotations

import numpy as np


def prism_vertices(poly2d: np.ndarray, thickness: float) -> np.ndarray:
    """(k, 2) polygon -> (2k, 3) prism vertices, z in [0, thickness]."""
    k = len(poly2d)
    z0 = np.zeros((k, 1))
    return np.vstack([np.hstack([poly2d, z0]), np.hstack([poly2d, z0 + thickness])])


def pad6(gen: np.ndarray, dim: int) -> np.ndarray:
    """(n, 3) 2D generalised forces [Fx, Fy, Mz] -> (n, 6); 3D arrays unchanged."""
    if dim == 3:
        return np.asarray(gen, dtype=float)
    g = np.asarray(gen, dtype=float)
    out = np.zeros((len(g), 6))
    out[:, 0:2] = g[:, 0:2]
    out[:, 5] = g[:, 2]
    return out


def rho_g(scene) -> float:
    """rho |g| (N/m^3) of the free blocks (mass-weighted mean density); kn = rho_g / eps."""
    free = [b for b in scene.blocks if not b.fixed] or scene.blocks
    rho = sum(b.mass for b in free) / sum(b.volume for b in free)
    return rho * float(np.linalg.norm(scene.gravity))


def yade_blocked(dim: int, blocked) -> str:
    """YADE's ``blockedDOFs`` letters (x y z translations, X Y Z rotations) of a block's
    blocked dofs (indices into 2D [x, y, rz] or 3D [x, y, z, rx, ry, rz]); a 2D scene's
    prisms also have z, X, Y blocked."""
    letters = ("x", "y", "Z") if dim == 2 else ("x", "y", "z", "X", "Y", "Z")
    out = "".join(letters[j] for j in blocked)
    return out + ("zXY" if dim == 2 else "")


def build_job(scene, interfaces, f0, fL, params: dict, result="result.json") -> dict:
    """The job dict for one YADE run (all the stiffnesses of ``params["eps"]``)."""
    blocks = []
    for b in scene.blocks:
        v = np.asarray(b.poly.vertices, dtype=float)
        if scene.dim == 2:
            v = prism_vertices(v, scene.thickness)
        blocks.append({"id": b.id, "fixed": bool(b.fixed), "mass": float(b.mass), "vertices": v.tolist(),
                       "blocked": yade_blocked(scene.dim, b.blocked)})
    return {
        "format": "dem-job/1",
        "name": scene.name,
        "dim": scene.dim,
        "thickness": float(scene.thickness),
        "blocks": blocks,
        "f0": pad6(f0, scene.dim).tolist(),
        "fL": pad6(fL, scene.dim).tolist(),
        "interfaces": [[int(a), int(b), float(s)] for a, b, s in zip(interfaces.a, interfaces.b, interfaces.area)],
        "friction": float(scene.friction),
        "friction_pairs": [[int(i), int(j), float(mu)] for (i, j), mu in sorted(scene.friction_pairs.items())],
        "rho_g": rho_g(scene),
        "gravity_norm": float(np.linalg.norm(scene.gravity)),
        "params": dict(params),
        "result": result,
    }
