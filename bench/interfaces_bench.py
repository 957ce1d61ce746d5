"""Scene loading and interface detection time against block count (2D and 3D walls)."""
from __future__ import annotations

import math

import pandas as pd

from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene
from scenes import builders as B

from .common import out_dir, timed


def main(sizes=(100, 1000, 3000, 10000)) -> pd.DataFrame:
    rows = []
    for dim in (2, 3):
        for n in sizes:
            side = int(round(math.sqrt(n)))
            data = B.running_bond_wall(side, side, dim=dim)
            t_load, scene = timed(lambda: load_scene(data))
            t_if, I = timed(lambda: find_interfaces(scene))
            rows.append({"dim": dim, "n_blocks": scene.n_blocks, "n_interfaces": len(I),
                         "load_s": t_load, "interfaces_s": t_if})
            print(f"interfaces {dim}D {scene.n_blocks:6d} blocks: load {t_load:.3f} s, "
                  f"interfaces {t_if:.3f} s ({len(I)} found)", flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(out_dir() / "interfaces.csv", index=False)
    return df


if __name__ == "__main__":
    main()
