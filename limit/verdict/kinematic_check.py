"""Linear kinematic analysis of a local mechanism, as Italian practice assesses masonry
(NTC 2018, section 8.7.1; Circolare 21 January 2019 n. 7, C8.7.1, after the earlier
Circolare 617/2009, C8A.4): the collapse multiplier and mechanism of the limit analysis
turned into the participating mass and the spectral acceleration that activates the
mechanism.

With P_i the weights moved by the mechanism (N; here each free block's self weight at
its centroid and the dead point forces at their points, their components along gravity)
and dx_i the virtual horizontal displacements of their points of application along the
live load's horizontal direction (m; any scale, only ratios enter):

* participating mass  M* = (sum P_i dx_i)^2 / (g sum P_i dx_i^2)        (kg)
* mass fraction       e* = g M* / sum P_i                               (-)
* spectral activation acceleration  a0* = alpha0 g / (e* FC)            (m/s^2)

(Circolare 617/2009 eqs. C8A.4.3-C8A.4.4, kept by the 2019 Circolare's C8.7.1; FC is the
confidence factor, 1.35 for knowledge level LC1.) The sums run over the weights whose
point of application moves (|velocity| above ``MOVING`` x the largest).
"""
from __future__ import annotations

import numpy as np

from limit.model.dims import rigid_velocity
from limit.model.loads import horizontal_direction  # noqa: F401 - part of this module's interface

#: a point of application moves when its speed exceeds this fraction of the largest
MOVING = 1e-6
#: confidence factor of knowledge level LC1 (NTC 2018 C8.5.4, Table C8.5.IV)
FC_DEFAULT = 1.35


def weights(scene) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(block index (k,), point (k, d) m, P (k,) N) of every weight on a free block: each
    block's self weight at its centroid (when the dead load has one) and each dead point
    force at its point; P is the force's component along gravity (downward positive)."""
    g = np.asarray(scene.gravity, dtype=float)
    gn = float(np.linalg.norm(g))
    down = g / gn
    free = set(int(i) for i in scene.free)
    idx, pts, P = [], [], []
    for ld in scene.dead:
        blocks = [i for i in ld["_blocks"] if i in free]
        if ld["type"] == "self_weight":
            for i in blocks:
                idx.append(i), pts.append(scene.blocks[i].centroid), P.append(scene.blocks[i].mass * gn)
        elif ld["type"] == "point_force" and blocks:
            i = blocks[0]
            p = np.asarray(ld.get("point", scene.blocks[i].centroid), dtype=float)
            f = float(np.asarray(ld["force"], dtype=float) @ down)
            if f != 0.0:
                idx.append(i), pts.append(p), P.append(f)
    d = scene.dim
    return (np.asarray(idx, dtype=int), np.asarray(pts, dtype=float).reshape(-1, d), np.asarray(P, dtype=float))


def point_velocities(scene, mechanism: dict, idx: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """(k, d) velocities of the points ``pts`` (m) carried by blocks ``idx`` in the
    mechanism {block id: generalised velocity at the centroid} (2D [ux, uy, rz], 3D
    [ux, uy, uz, rx, ry, rz]): v = u + w x (p - c)."""
    d = scene.dim
    out = np.zeros((len(idx), d))
    for k, (i, p) in enumerate(zip(idx, pts)):
        b = scene.blocks[int(i)]
        m = mechanism.get(b.id)
        if m is None:
            continue
        out[k] = rigid_velocity(m, p - b.centroid, d)
    return out


def linear(scene, mechanism: dict, alpha0: float, fc: float = FC_DEFAULT) -> dict:
    """The linear kinematic quantities of a mechanism with multiplier ``alpha0`` (module
    docstring): {"M_star" kg, "e_star", "a0_star" m/s^2, "a0_star_g" (in g), "sum_P" N
    (weights that move), "fc", "direction" (d,), "n_weights"}. Raises ValueError for a
    mechanism that moves no weight or moves it only vertically."""
    if not (np.isfinite(fc) and fc >= 1.0):
        raise ValueError(f"confidence factor FC must be a number >= 1, got {fc!r}")
    idx, pts, P = weights(scene)
    v = point_velocities(scene, mechanism, idx, pts)
    speed = np.linalg.norm(v, axis=1)
    moving = speed > MOVING * max(float(speed.max(initial=0.0)), 1e-300)
    if not moving.any():
        raise ValueError("the mechanism moves no weight")
    dirn = horizontal_direction(scene)
    dx = v[moving] @ dirn
    Pm = P[moving]
    g = float(np.linalg.norm(scene.gravity))
    num, den = float(Pm @ dx) ** 2, float(Pm @ dx ** 2)
    if den <= 0.0:
        raise ValueError("the mechanism moves its weights only vertically: no horizontal participation")
    M = num / (g * den)
    sumP = float(Pm.sum())
    e = g * M / sumP
    a0 = alpha0 * g / (e * fc)
    return {"M_star": M, "e_star": e, "a0_star": a0, "a0_star_g": a0 / g, "sum_P": sumP, "fc": fc,
            "direction": dirn.tolist(), "n_weights": int(moving.sum())}
