"""Capacity curves of the catalog's mechanisms (limit.verdict.local_check.capacity_curve): the joint
equations of a rocking mechanism, incremental limit analysis (limit.incremental_curve) where a joint
slides, with the default settings (curve_steps, curve_time_budget). Writes
bench/out/capacity_curves.md and .csv: per scene its method, time, steps, why the curve ends and d0."""
from __future__ import annotations

import time
from pathlib import Path

import pandas as pd

from .common import machine, out_dir

CATALOG = Path(__file__).resolve().parent.parent / "scenes" / "catalog"


def main() -> None:
    from limit.analysis import analyse
    from limit.incremental_curve import follow_frictional
    from limit.model.scene import load_scene
    from limit.verdict.local_check import capacity_curve, step_mechanism

    rows = []
    for path in sorted(CATALOG.glob("*.json")):
        scene = load_scene(path)
        m = step_mechanism(analyse(scene, verdict=False).data)
        if m is None:
            rows.append({"scene": path.stem, "method": "-", "why": "no mechanism"})
            continue
        t0 = time.perf_counter()
        curve, why = capacity_curve(scene, m[2], m[1], sliding=follow_frictional)
        dt = time.perf_counter() - t0
        c = curve or {}
        rows.append({"scene": path.stem, "free_blocks": len(scene.free), "alpha0": m[1],
                     "method": c.get("method", "rocking") if curve else "-", "time_s": round(dt, 1),
                     "steps": c.get("steps", len(c.get("alpha", [])) - 1 if curve else None),
                     "end": c.get("stop", "alpha 0" if c.get("d0") is not None else "") if curve else why,
                     "d0_m": c.get("d0")})
        print(f"  {path.stem}: {rows[-1]['method']} {dt:.1f} s", flush=True)
    df = pd.DataFrame(rows)
    out = out_dir()
    df.to_csv(out / "capacity_curves.csv", index=False)
    cols = list(df.columns)
    table = ["| " + " | ".join(cols) + " |", "|" + " --- |" * len(cols)]
    table += ["| " + " | ".join("" if pd.isna(v) else f"{v:.6g}" if isinstance(v, float) else str(v) for v in r) + " |"
              for r in df[cols].itertuples(index=False)]
    text = f"# Capacity curves of the catalog's mechanisms ({machine()})\n\n" + "\n".join(table) + "\n"
    (out / "capacity_curves.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
