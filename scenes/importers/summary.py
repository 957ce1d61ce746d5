"""The import's record (``meta.import`` of the scene) and its printed summary.

Lengths in the record are in metres, volumes in m^3 (2D: m^2 of outline area), mass in kg.
"""
from __future__ import annotations

import numpy as np


def record(files, units: str, scale: float, built, mass: float, tolerance: float,
           n_interfaces, fixed: list, warnings: list) -> dict:
    """The ``meta.import`` dict: what was read, what the repair did, per-block ratios."""
    per = []
    for b in built.blocks:
        per.append({"id": b.id, "source": b.source, "kind": "compound" if b.parts else "convex",
                    "parts": len(b.parts) if b.parts else 1,
                    "hull_ratio": round(float(b.hull_ratio), 6),
                    "volume_ratio": round(float(b.volume / b.mesh_volume), 6),
                    **({"notes": b.notes} if b.notes else {})})
    d = built.dim
    return {
        "files": [str(f) for f in files],
        "units": units,
        "dim": d,
        "blocks": len(built.blocks),
        "hulls": sum(1 for b in built.blocks if not b.parts),
        "compound_blocks": sum(1 for b in built.blocks if b.parts),
        "parts": sum(len(b.parts) if b.parts else 1 for b in built.blocks),
        "joints_snapped": built.n_joints,
        "interfaces": n_interfaces,
        "largest_gap_closed_m": built.gap_max * scale,
        "largest_overlap_closed_m": built.overlap_max * scale,
        "mass_kg": mass,
        "fixed": fixed,
        "tolerance": {"scene_m": tolerance, "merge_m": built.tol["merge"] * scale, "gap_m": built.tol["gap"] * scale,
                      "flat_m": built.tol["flat"] * scale, "angle_deg": built.tol["angle_deg"],
                      "volume": built.tol["vol_tol"], "median_block_width_m": built.tol["median_width"] * scale},
        "planarity_residual_m": built.residual * scale,
        "largest_corner_move_m": built.moved * scale,
        "tilted_joints": {"count": built.tilted[0], "largest_angle_deg": built.tilted[1],
                          "largest_separation_m": built.tilted[2] * scale},
        "warnings": list(warnings),
        "per_block": per,
    }


def _len(x: float) -> str:
    x = abs(x) if abs(x) < 1e-15 else x
    return f"{x * 1000:.3g} mm" if abs(x) < 1 else f"{x:.4g} m"


def text(rec: dict, out_path: str) -> str:
    """The printed summary: blocks, hulls, compound blocks, interfaces, gaps closed, mass."""
    ratios = np.array([b["hull_ratio"] for b in rec["per_block"]])
    vr = np.array([b["volume_ratio"] for b in rec["per_block"]])
    lines = [
        f"read {', '.join(rec['files'])} (units {rec['units']}, {rec['dim']}D)",
        f"blocks: {rec['blocks']} ({rec['hulls']} convex hulls, {rec['compound_blocks']} compound"
        + (f" of {rec['parts'] - rec['hulls']} convex parts" if rec['compound_blocks'] else "")
        + f"); fixed: {len(rec['fixed'])}",
        f"hull/mesh volume ratio per block: min {ratios.min():.4f}, max {ratios.max():.4f} "
        f"(convex up to {1 + rec['tolerance']['volume']:.4g}); output/mesh volume: {vr.min():.4f} to {vr.max():.4f}",
        f"joints snapped to their mid-plane: {rec['joints_snapped']}; largest gap closed "
        f"{_len(rec['largest_gap_closed_m'])}, largest overlap closed {_len(rec['largest_overlap_closed_m'])} "
        f"(gap tolerance {_len(rec['tolerance']['gap_m'])}); largest corner move {_len(rec['largest_corner_move_m'])}",
        *([f"joints whose faces kept different planes: {rec['tilted_joints']['count']} (up to "
           f"{rec['tilted_joints']['largest_angle_deg']:.3g} deg and "
           f"{_len(rec['tilted_joints']['largest_separation_m'])} apart; taken as joints through "
           f"interfaces.angle_tolerance and tolerance {_len(rec['tolerance']['scene_m'])})"]
          if rec.get("tilted_joints", {}).get("count") else []),
        f"interfaces: {rec['interfaces'] if rec['interfaces'] is not None else 'not counted'}",
        f"mass: {rec['mass_kg']:.6g} kg",
        f"wrote {out_path}",
    ]
    return "\n".join(lines)
