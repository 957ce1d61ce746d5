"""A scene dict with its live load turned about the vertical: the direction sweep's directions
(:mod:`limit.direction_sweep`) and step 2's starts from nearby directions (:mod:`limit.analysis`)."""
from __future__ import annotations

import copy
import math

import numpy as np


def turned(data: dict, theta_deg: float, verdict: bool = False) -> dict:
    """The scene dict with every live body force turned by theta about the vertical (without its
    seismic demand unless ``verdict``: the code check is made at the minimum only)."""
    g = np.asarray(data.get("gravity", [0.0, 0.0, -9.81]), dtype=float)
    up = -g / np.linalg.norm(g)
    out = copy.deepcopy(data)
    t = math.radians(theta_deg)
    for k, ld in enumerate(out["loads"]["live"]):
        if ld.get("type") != "body_force":
            raise ValueError(f"loads.live[{k}]: only body forces turn with the load direction, not {ld.get('type')!r}")
        d = np.asarray(ld["direction"], dtype=float)
        v = (d @ up) * up
        h = d - v  # Rodrigues about the vertical: h cos t + (up x h) sin t
        ld["direction"] = (v + h * math.cos(t) + np.cross(up, h) * math.sin(t)).tolist()
    out["name"] = f"{data.get('name', 'scene')}@{theta_deg:g}deg"
    if not verdict:
        out.pop("demand", None)
    return out
