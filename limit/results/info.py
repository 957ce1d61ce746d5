"""Scene summary for ``python -m limit info`` (docs/formats.md, 'Commands')."""
from __future__ import annotations

from limit.geom.interfaces import find_interfaces
from limit.model.pair_checks import check_friction_pairs


def scene_info(scene, interfaces=None) -> dict:
    """Counts, total mass (kg) and bounding box ([[min...], [max...]], m) of a scene."""
    I = find_interfaces(scene) if interfaces is None else interfaces
    check_friction_pairs(scene, I)
    return {
        "name": scene.name,
        "dim": scene.dim,
        "n_blocks": scene.n_blocks,
        "n_fixed_blocks": scene.n_fixed,
        "n_interfaces": len(I),
        "mass": scene.total_mass,
        "bbox": scene.bbox().tolist(),
        "units": {"length": "m", "mass": "kg"},
    }


def format_info(info: dict) -> str:
    lo, hi = info["bbox"]
    fmt = lambda v: "[" + ", ".join(f"{x:.4g}" for x in v) + "]"
    return (f"{info['name']}: {info['dim']}D, {info['n_blocks']} blocks "
            f"({info['n_fixed_blocks']} fixed), {info['n_interfaces']} interfaces, "
            f"mass {info['mass']:.6g} kg, bbox {fmt(lo)} .. {fmt(hi)} m")
