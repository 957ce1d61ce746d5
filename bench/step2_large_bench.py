"""Step 2 at scale: the large-scale route (limit/solve/step2_large.py) on running-bond walls.

1. 2D walls (0.4 x 0.3 m blocks, mu 0.9, horizontal body force) of 30 to 10,000
   blocks and 3D walls of up to 3,000: LP alpha, the route's verified alpha (best and
   worst over its starts), time (wall clock, starts on both cores), starts.
2. Against today's route (the successive LP with restarts, 120 s budget) on the walls
   of 30 to 300 blocks: the same wall, both alphas, both times.
The time limit of the whole route is ``$STEP2_BENCH_BUDGET`` s (default 600).
Writes bench/out/step2_large.csv and step2_large.md.
"""
from __future__ import annotations

import math
import os
import time

import pandas as pd

from limit import step2
from limit.settings import DEFAULT
from limit.solve import nlp, step2_large
from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from scenes import builders as B

from .common import machine, out_dir

SIZES_2D = (30, 100, 300, 1000, 3000, 10000)
SIZES_3D = (300, 1000, 3000)
COMPARE_MAX = 300  # today's route is run up to this many blocks
BUDGET = float(os.environ.get("STEP2_BENCH_BUDGET", 600.0))


def wall(n, dim=2, mu=0.9):
    """A running-bond wall of about n blocks, courses:blocks per course about 1:1 in 2D,
    1:3 in 3D (a 3D wall is one block thick)."""
    if dim == 2:
        courses = max(2, int(round(math.sqrt(n))))
        return B.running_bond_wall(courses, max(2, int(round(n / courses))), dim=2, L=0.4, H=0.3, mu=mu)
    courses = max(2, int(round(math.sqrt(n / 3))))
    return B.running_bond_wall(courses, max(2, int(round(n / courses))), dim=3, mu=mu)


def one(n, dim) -> dict:
    P = assemble(load_scene(wall(n, dim)))
    t = time.perf_counter()
    sol, _, _ = solve_lp(P)
    lp_s = time.perf_counter() - t
    t = time.perf_counter()
    big = step2_large.solve(P, sol, time_budget=BUDGET)
    row = {"dim": dim, "blocks": P.n_dof // P.scene.ndof, "alpha_lp": sol.alpha, "lp_s": lp_s,
           "alpha": big.alpha if big.ok else None, "alpha_worst": big.alpha_worst,
           "verified": big.ok, "time_s": time.perf_counter() - t, "starts": len(big.starts),
           "n_verified": big.n_verified or 0, "workers": big.workers,
           "iterations": sum(r.get("iterations", 0) for r in big.starts), "reason": big.reason}
    if dim == 2 and n <= COMPARE_MAX:
        t = time.perf_counter()
        today = step2.run(P, sol)
        row.update(today_alpha=today.alpha if today.ok else None, today_s=time.perf_counter() - t)
    row["auto_alpha"] = auto_alpha(row, P.n_dof // P.scene.ndof)
    print(f"step2-large {dim}D {row['blocks']:6d} blocks LP {sol.alpha:.5f} route {row['alpha']} "
          f"({row['time_s']:.1f} s, {row['n_verified']}/{row['starts']} starts verified) "
          f"today {row.get('today_alpha')} ({row.get('today_s', float('nan')):.1f} s)", flush=True)
    return row


def auto_alpha(row: dict, n_free: int) -> float | None:
    """The alpha ``limit solve --method auto`` keeps from the two routes measured in ``row``: from
    the setting large_min_free free blocks on the large route's; below, the lower verified one
    (the settings also_iterative and lower_by, step2.prefer_large), at the default settings."""
    big, today = row.get("alpha"), row.get("today_alpha")
    if n_free >= DEFAULT.large_min_free or today is None:
        return big
    return big if DEFAULT.also_iterative and step2.prefer_large(today, big, DEFAULT.lower_by) else today


def main(sizes_2d=SIZES_2D, sizes_3d=SIZES_3D) -> pd.DataFrame:
    out = out_dir()
    rows = []
    for dim, sizes in ((2, sizes_2d), (3, sizes_3d)):
        for n in sizes:
            rows.append(one(n, dim))
            pd.DataFrame(rows).to_csv(out / "step2_large.csv", index=False)  # kept as it grows
    df = pd.DataFrame(rows)
    m = machine()
    fmt = lambda v, f: "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, f)
    lines = [f"# Step 2 at scale ({m['cpus']} CPUs, Python {m['python']}): iterative LP on ipm, snapped and "
             f"checked; budget {BUDGET:g} s", "",
             "Walls in running bond, mu 0.9. 'route' is the lowest verified alpha over the starts (each one a "
             "frictional collapse state, an upper bound of the global minimum); 'today' is the successive LP "
             "with its restarts (120 s budget), run up to 300 blocks. 'auto' is what `--method auto` keeps: "
             f"below {DEFAULT.large_min_free} free blocks the lower of the two (never above 'today'), from there "
             "the route's.", "",
             "| dim | blocks | LP alpha | route alpha | worst start | verified starts | time s | LP s | "
             "today alpha | today s | auto alpha |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for _, r in df.iterrows():
        lines.append(f"| {r['dim']} | {r['blocks']} | {r['alpha_lp']:.5f} | {fmt(r['alpha'], '.5f')} | "
                     f"{fmt(r['alpha_worst'], '.5f')} | {r['n_verified']}/{r['starts']} | {r['time_s']:.1f} | "
                     f"{r['lp_s']:.1f} | {fmt(r.get('today_alpha'), '.5f')} | {fmt(r.get('today_s'), '.1f')} | "
                     f"{fmt(r.get('auto_alpha'), '.5f')} |")
    (out / "step2_large.md").write_text("\n".join(lines) + "\n")
    return df
