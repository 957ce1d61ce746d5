"""DEM block models side by side: YADE Polyhedra against the vertex-to-face model.

Scenes: single blocks (rocking, sliding), the 3-block stack, the portal, a
12 x 2 running-bond wall, the 9-voussoir arch, the 3D segmental arch, the 3D
6 x 5 wall and the paper's Fig. 4 (catalog files where they exist). Each runs
once with each model at its defaults (``dem_validation.params.BY_CONTACT``),
two YADE runs at a time (one per core), the costliest first (Polyhedra before
the vertex model, bigger scenes first) so that the long runs do not form a tail. A Polyhedra run is stopped at POLY_CAP seconds: its time is then
a lower bound, and so is the speed-up.

The reference is the limit analysis: the scene's closed form where it has one,
else the frictional alpha of :func:`limit.analysis.analyse` (the LP where the
frictional step is not needed). Writes bench/out/dem_models.csv and
dem_models.md (time, alpha, error against the reference, steps, ms per step,
speed-up; the median speed-up) and dem_models.png (time per scene, log).

Time is the YADE process's CPU time (``cpu_s``, read from /proc when a capped
run is killed), which stays comparable when the machine is shared.
"""
from __future__ import annotations

import os
import statistics
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd

from dem_validation import run_scene
from limit.model.scene import load_scene
from scenes import builders as B

from .common import machine, out_dir

CATALOG = Path(__file__).resolve().parents[1] / "scenes" / "catalog"
#: wall-clock cap of one run (s), either model; $DEM_BENCH_CAP overrides it. At 400 s the
#: Polyhedra runs of the three walls were cut short and the median speed-up was only a lower
#: bound (7.8x), so the default lets them finish
POLY_CAP = float(os.environ.get("DEM_BENCH_CAP", 1500.0))

SCENES = {
    "block-rocking-2d": lambda: str(CATALOG / "block-rocking-2d.json"),
    "block-sliding-2d": lambda: str(CATALOG / "block-sliding-2d.json"),
    "stack-3-2d": lambda: str(CATALOG / "stack-3-2d.json"),
    "portal-2d": lambda: str(CATALOG / "portal-2d.json"),
    "wall-12x2-2d": lambda: B.running_bond_wall(12, 2, dim=2, mu=1.2, name="wall-12x2-2d"),
    "arch-semicircular-9-2d": lambda: str(CATALOG / "arch-semicircular-9-2d.json"),
    "arch-segmental-7-3d": lambda: str(CATALOG / "arch-segmental-7-3d.json"),
    "wall-6x5-3d": lambda: str(CATALOG / "wall-6x5-3d.json"),
    "paper-fig4-opus-africanum-2d": lambda: str(CATALOG / "paper-fig4-opus-africanum-2d.json"),
}
MODELS = ("vertex", "polyhedra")


def reference(scene) -> tuple[float | None, str]:
    """(alpha, kind) of the limit analysis: the closed form, else frictional, else LP."""
    from limit.analysis import analyse

    sc = load_scene(scene)
    if sc.expected.get("alpha") is not None:
        return float(sc.expected["alpha"]), "closed form"
    res = analyse(sc, method="auto", nlp_options={"global_check": False, "iterative": False}).data
    nlp = res.get("nlp") or {}
    if nlp.get("status") == "optimal" and nlp.get("alpha") is not None:
        return float(nlp["alpha"]), "NLP"
    return res["lp"].get("alpha"), "LP"


def _one(name: str, model: str) -> dict:
    last = {"step": 0}

    def progress(info):
        if "step" in info:
            last["step"] = max(last["step"], int(info["step"]))

    t0 = time.monotonic()
    dem = run_scene(SCENES[name](), timeout_s=POLY_CAP, contact=model, progress=progress)
    wall = time.monotonic() - t0
    capped = dem["status"] == "failed" and "timed out" in str(dem.get("reason", ""))
    steps = dem.get("steps") or last["step"]
    cpu = dem.get("cpu_s")
    return {"scene": name, "model": model, "status": dem["status"], "alpha": dem.get("alpha"),
            "wall_s": wall, "time_s": cpu if cpu else wall, "capped": capped, "steps": steps,
            "ms_per_step": 1e3 * (cpu if cpu else wall) / steps if steps else float("nan"),
            "runs": "/".join(f"{r['alpha']:.5f}" for r in dem.get("runs", []) if r.get("alpha") is not None),
            "reason": dem.get("reason", "")}


def main(scenes=tuple(SCENES), workers=2) -> pd.DataFrame:
    refs = {n: reference(SCENES[n]()) for n in scenes}
    size = {n: len(load_scene(SCENES[n]()).blocks) for n in scenes}
    jobs = sorted(((n, m) for n in scenes for m in MODELS),
                  key=lambda j: -(size[j[0]] * (20 if j[1] == "polyhedra" else 1)))
    rows = []
    with ThreadPoolExecutor(max_workers=workers) as pool:
        for row in pool.map(lambda j: _one(*j), jobs):
            a_ref, kind = refs[row["scene"]]
            row.update(reference=a_ref, ref_kind=kind,
                       err=(row["alpha"] / a_ref - 1.0) if (row["alpha"] is not None and a_ref) else float("nan"))
            rows.append(row)
            print(f"dem-models {row['scene']:30s} {row['model']:9s} {row['status']:9s} alpha={row['alpha']} "
                  f"ref={a_ref} err={100 * row['err']:+.2f}% time={row['time_s']:.1f}s"
                  f"{' (capped)' if row['capped'] else ''} {row['ms_per_step']:.3f} ms/step", flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(out_dir() / "dem_models.csv", index=False)
    table = summary(df)
    (out_dir() / "dem_models.md").write_text(table)
    print(table)
    _plot(df)
    return df


def summary(df: pd.DataFrame) -> str:
    """Markdown table, one row per scene, and the median speed-up (time and per step)."""
    v = df[df.model == "vertex"].set_index("scene")
    p = df[df.model == "polyhedra"].set_index("scene")
    lines = [f"DEM block models, {machine()}; time = CPU seconds of the YADE process; Polyhedra capped at "
             f"{POLY_CAP:g} s of wall clock ('>' marks a capped time: its speed-up is a lower bound)", "",
             "| scene | reference | vertex alpha | err | time s | Polyhedra alpha | err | time s | speed-up | "
             "per-step ratio |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    speed, per_step = [], []
    for name in v.index:
        a, b = v.loc[name], p.loc[name] if name in p.index else None
        sp = b["time_s"] / a["time_s"] if b is not None else float("nan")
        ps = b["ms_per_step"] / a["ms_per_step"] if b is not None else float("nan")
        speed.append(sp)
        per_step.append(ps)

        def fmt(r):
            if r is None:
                return "-", "-", "-"
            al = f"{r['alpha']:.4f}" if r["alpha"] is not None and np.isfinite(r["alpha"]) else r["status"]
            er = f"{100 * r['err']:+.2f} %" if np.isfinite(r["err"]) else "-"
            return al, er, (">" if r["capped"] else "") + f"{r['time_s']:.0f}"

        ref = f"{a['reference']:.4f} ({a['ref_kind']})" if a["reference"] is not None else "-"
        lines.append(f"| {name} | {ref} | {' | '.join(fmt(a))} | {' | '.join(fmt(b))} | "
                     f"{'>' if b is not None and b['capped'] else ''}{sp:.1f}x | {ps:.1f}x |")
    ok = [s for s in speed if np.isfinite(s)]
    oks = [s for s in per_step if np.isfinite(s)]
    lines += ["", f"median speed-up (whole runs): {statistics.median(ok):.1f}x over {len(ok)} scenes; "
                  f"median per-step cost ratio: {statistics.median(oks):.1f}x"]
    return "\n".join(lines) + "\n"


def _plot(df):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = df[df.model == "vertex"].set_index("scene")
    p = df[df.model == "polyhedra"].set_index("scene").reindex(v.index)
    y = np.arange(len(v))
    fig, ax = plt.subplots(figsize=(8, 0.45 * len(v) + 1.5))
    ax.barh(y - 0.2, v["time_s"], height=0.38, label="vertex-to-face", color="#55a868")
    ax.barh(y + 0.2, p["time_s"], height=0.38, label="Polyhedra (hatched: capped)", color="#c44e52",
            hatch=None)
    for k, capped in enumerate(p["capped"].fillna(False)):
        if capped:
            ax.barh(y[k] + 0.2, p["time_s"].iloc[k], height=0.38, fill=False, hatch="//", edgecolor="k")
    ax.set_yticks(y)
    ax.set_yticklabels(v.index, fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("CPU time of the whole DEM run (s)")
    ax.set_title("DEM run time per scene: vertex-to-face model against YADE Polyhedra", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, axis="x", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out_dir() / "dem_models.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main(tuple(sys.argv[1:]) or tuple(SCENES))
