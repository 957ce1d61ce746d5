"""Rigid motions and scaling of whole scenes (for invariance checks and reuse).

:func:`transform` maps every block to ``x -> s * R x + t`` (blocks become
vertex lists), rotates gravity, load vectors and pressures' face normals with ``R``,
moves load points and tie ends with the full map and pressures' levels with its part
along the vertical. Force magnitudes (and capacities, pressures, stresses) are left alone; a uniform scale
``s`` changes masses by s^dim (and by s again through the thickness in 2D when
``scale_thickness``).
"""
from __future__ import annotations

import copy

import numpy as np

from limit.geom import geometry
def block_vertices(blk: dict, dim: int) -> np.ndarray:
    """The corner points of a block dict (box or vertices), (k, dim)."""
    if "vertices" in blk:
        return np.asarray(blk["vertices"], dtype=float)
    bx = blk["box"]
    rot = None
    if "rotation" in bx:
        rot = geometry.rotation_matrix(dim, bx["rotation"]["angle_deg"], bx["rotation"].get("axis"))
    return geometry.box(bx["center"], bx["size"], rot).vertices


def transform(scene: dict, R=None, t=None, s: float = 1.0, scale_thickness: bool = True) -> dict:
    """A copy of the scene dict moved by rotation R (d, d), translation t (d,), scale s > 0."""
    d = scene["dim"]
    R = np.eye(d) if R is None else np.asarray(R, dtype=float)
    t = np.zeros(d) if t is None else np.asarray(t, dtype=float)
    out = copy.deepcopy(scene)
    mapx = lambda x: (s * np.asarray(x, dtype=float) @ R.T + t).tolist()
    rot = lambda v: (np.asarray(v, dtype=float) @ R.T).tolist()
    for blk in out["blocks"]:
        v = block_vertices(blk, d)
        blk.pop("box", None)
        blk["vertices"] = mapx(v)
    if "gravity" in out:
        out["gravity"] = rot(out["gravity"])
    elif d == 2 and not np.allclose(R, np.eye(2)):
        out["gravity"] = rot([0.0, -9.81])
    elif d == 3 and not np.allclose(R, np.eye(3)):
        out["gravity"] = rot([0.0, 0.0, -9.81])
    for kind in ("dead", "live"):
        for ld in out.get("loads", {}).get(kind, []):
            if "direction" in ld:
                ld["direction"] = rot(ld["direction"])
            if "force" in ld:
                ld["force"] = rot(ld["force"])
            if "point" in ld:
                ld["point"] = mapx(ld["point"])
            if "face" in ld:
                ld["face"] = rot(ld["face"])
            if "level" in ld:  # a height along -gravity: scaled, and moved by t's part along it
                g = np.asarray(out.get("gravity", [0.0, -9.81] if d == 2 else [0.0, 0.0, -9.81]), dtype=float)
                ld["level"] = float(s * ld["level"] + t @ (-g / np.linalg.norm(g)))
    for tie in out.get("ties", []):
        for side in ("from", "to"):
            if isinstance(tie.get(side), dict) and "point" in tie[side]:
                tie[side]["point"] = mapx(tie[side]["point"])
    for g in out.get("joints", []):
        plane = (g.get("between") or {}).get("plane")
        if isinstance(plane, dict) and "point" in plane and "normal" in plane:
            plane["point"], plane["normal"] = mapx(plane["point"]), rot(plane["normal"])
    if d == 2 and scale_thickness and s != 1.0:
        out["thickness"] = out.get("thickness", 1.0) * s
    if "tolerance" in out:
        out["tolerance"] = out["tolerance"] * s
    return out


def reorder(scene: dict, seed: int = 0) -> dict:
    """A copy with the blocks in a random order (ids unchanged)."""
    out = copy.deepcopy(scene)
    rng = np.random.default_rng(seed)
    perm = rng.permutation(len(out["blocks"]))
    out["blocks"] = [out["blocks"][i] for i in perm]
    return out


def random_rotation(dim: int, rng) -> np.ndarray:
    if dim == 2:
        return geometry.rotation_matrix(2, float(rng.uniform(0, 360)))
    from scipy.spatial.transform import Rotation

    return Rotation.random(random_state=rng).as_matrix()
