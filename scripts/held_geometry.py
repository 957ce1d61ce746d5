"""A scene moved to a YADE run's pose at its highest equilibrium, to run the limit analysis on the
geometry the engine had just before it collapsed.

    python scripts/held_geometry.py SCENE.json YADE.json OUT.json [--scale S] [--tolerance T]
        [--angle DEG]

``YADE.json``: a ``python -m dem_validation run ... --json`` file; its stiffest run with a
``held_pose`` (docs/formats.md) is used. Each free block is turned by its rotation vector about
its centroid and moved by its displacement (both times ``--scale``). The moved joints no longer
meet exactly, so the written scene carries ``tolerance`` (m) and ``interfaces.angle_tolerance``
(degrees) for the interface search."""
from __future__ import annotations

import argparse
import json

import numpy as np
from scipy.spatial.transform import Rotation

from limit.model.scene import load_scene


def held_pose(dem: dict) -> tuple[float, dict]:
    """(the run's highest equilibrium alpha, its held_pose) of the stiffest run that has one."""
    dem = dem.get("dem", dem)
    runs = sorted((r for r in dem.get("runs") or [] if r.get("held_pose")), key=lambda r: -r["eps"])
    if not runs:
        raise SystemExit("no run with a held_pose in the DEM file (a collapsed YADE run records one)")
    return runs[-1]["alpha_lo"], runs[-1]["held_pose"]


def moved(scene_path: str, pose: dict, scale: float, tolerance: float, angle: float) -> dict:
    """The scene's JSON with every free block in ``pose`` moved to it (m, rad; scene axes)."""
    with open(scene_path) as fh:
        data = json.load(fh)
    loaded = {b.id: b for b in load_scene(scene_path).blocks}
    for bd in data["blocks"]:
        p = pose.get(bd["id"])
        if p is None:
            continue
        if "parts" in bd:
            raise SystemExit(f"block {bd['id']!r}: compound blocks are not moved by this script")
        b = loaded[bd["id"]]
        c = np.asarray(b.centroid)
        R = Rotation.from_rotvec(scale * np.asarray(p[3:6])).as_matrix()
        bd.pop("box", None)
        bd["vertices"] = ((np.asarray(b.poly.vertices) - c) @ R.T + c + scale * np.asarray(p[:3])).tolist()
    data["tolerance"] = tolerance
    data["interfaces"] = dict(data.get("interfaces", {}), angle_tolerance=angle)
    return data


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("dem")
    ap.add_argument("out")
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies the pose (default 1)")
    ap.add_argument("--tolerance", type=float, default=1e-3, help="m (default 1e-3)")
    ap.add_argument("--angle", type=float, default=1.0, help="degrees (default 1)")
    a = ap.parse_args()
    with open(a.dem) as fh:
        alpha, pose = held_pose(json.load(fh))
    if len(next(iter(pose.values()))) != 6:
        raise SystemExit("held_pose of a 3D scene expected ([ux, uy, uz, rx, ry, rz] per block)")
    u = max(np.linalg.norm(v[:3]) for v in pose.values())
    r = max(np.linalg.norm(v[3:]) for v in pose.values())
    print(f"held at alpha {alpha:.5g}: largest displacement {u * 1e3:.3g} mm, rotation {r * 1e3:.3g} mrad")
    with open(a.out, "w") as fh:
        json.dump(moved(a.scene, pose, a.scale, a.tolerance, a.angle), fh)


if __name__ == "__main__":
    main()
