"""The scene key ``units``: the unit of the file's lengths, converted to metres before anything
downstream reads the scene (docs/formats.md, 'Scene file').

Lengths are the blocks' ``box.center`` and ``box.size``, ``vertices`` and ``parts[*].vertices``,
the ``point`` of a point force, of a tie's ends and of a joint group's plane, a pressure's ``level``, ``tolerance`` and (2D)
``thickness``. Everything else keeps its SI unit whatever ``units`` says: gravity (m/s^2), density
(kg/m^3), forces (N), pressures (Pa) and their gradients (Pa/m), the ``demand``'s ``Z`` and ``H``
(m, building data of the code check).
"""
from __future__ import annotations

import copy

#: metres per unit of the file
FACTORS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
DEFAULT = "m"


def to_metres(data: dict) -> dict:
    """The validated scene dict with every length in metres and ``units`` "m": ``data`` itself
    when its lengths are metres already, else a converted copy."""
    k = FACTORS[data.get("units", DEFAULT)]
    if k == 1.0:
        return data
    out = copy.deepcopy(data)
    out["units"] = "m"
    for key in ("tolerance", "thickness"):
        if key in out:
            out[key] = out[key] * k
    for bd in out["blocks"]:
        if "box" in bd:
            bd["box"]["center"] = _scaled(bd["box"]["center"], k)
            bd["box"]["size"] = _scaled(bd["box"]["size"], k)
        if "vertices" in bd:
            bd["vertices"] = [_scaled(v, k) for v in bd["vertices"]]
        for part in bd.get("parts", []):
            part["vertices"] = [_scaled(v, k) for v in part["vertices"]]
    for case in out.get("loads", {}).values():
        for ld in case:
            if "point" in ld:
                ld["point"] = _scaled(ld["point"], k)
            if isinstance(ld.get("level"), (int, float)) and not isinstance(ld.get("level"), bool):
                ld["level"] = ld["level"] * k
    for g in out.get("joints", []):
        plane = (g.get("between") or {}).get("plane") if isinstance(g, dict) else None
        if isinstance(plane, dict) and isinstance(plane.get("point"), list):
            plane["point"] = _scaled(plane["point"], k)
    for tie in out.get("ties", []):
        for side in ("from", "to"):
            if isinstance(tie.get(side), dict) and isinstance(tie[side].get("point"), list):
                tie[side]["point"] = _scaled(tie[side]["point"], k)
    return out


def _scaled(vec, k: float) -> list:
    return [x * k for x in vec]
