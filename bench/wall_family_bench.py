"""Step 2 on the generated wall family (scenes/generators/families.py), not on the benchmark walls.

Each member is solved as ``limit solve`` does it (the LP, then step 2 with ``method="auto"``):
whether step 2 verified, its alpha against the LP's, the route, the time, the number of LPs
(iterations over every start) and the spread of the verified alphas over the starts. A run is
a success when step 2 verifies, or when it is skipped because the LP's own point passes the
frictional check.

``$WALL_FAMILY_COUNT`` members (default 24) of ``$WALL_FAMILY_SEED`` (default 0), about
``$WALL_FAMILY_MIN`` to ``$WALL_FAMILY_MAX`` blocks (default 100 to 10,000).
``python -m bench.wall_family_bench [INDEX...]`` runs only those members.
Writes bench/out/wall_family.csv (row by row), wall_family.md and wall_family.png.
"""
from __future__ import annotations

import math
import os
import sys
import time

import pandas as pd

from limit import step2
from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from scenes.generators.families import wall_family

from .common import machine, out_dir

SEED = int(os.environ.get("WALL_FAMILY_SEED", 0))
COUNT = int(os.environ.get("WALL_FAMILY_COUNT", 24))
BLOCKS = (int(os.environ.get("WALL_FAMILY_MIN", 100)), int(os.environ.get("WALL_FAMILY_MAX", 10000)))


def one(scene: dict) -> dict:
    """The row of one member."""
    f = scene["meta"]["family"]
    P = assemble(load_scene(scene))
    t = time.perf_counter()
    sol, _, _ = solve_lp(P)
    lp_s = time.perf_counter() - t
    t = time.perf_counter()
    part = step2.step2(P, sol)
    runs = part.get("runs") or []
    ok = part["status"] in ("optimal", "skipped") and part.get("alpha") is not None
    row = {"index": f["index"], "dim": f["dim"], "blocks": P.n_dof // P.scene.ndof, "mu": f["mu"], "bond": f["bond"],
           "openings": f["openings"], "aspect": round(f["aspect"], 2), "angle_deg": f["angle_deg"],
           "alpha_lp": sol.alpha, "lp_s": lp_s, "verified": ok, "alpha": part.get("alpha") if ok else None,
           "status": part["status"], "route": part.get("route", "lp-point"), "time_s": time.perf_counter() - t,
           "lps": sum(int(r.get("iterations") or 0) for r in runs),
           "alpha_best": part.get("alpha_best"), "alpha_worst": part.get("alpha_worst"),
           "n_verified": part.get("n_verified"), "starts": part.get("n_starts"),
           "reason": "" if ok else str(part.get("reason", ""))[:300]}
    print(f"wall-family {row['index']:3d} {row['dim']}D {row['blocks']:6d} blocks mu {row['mu']:g} {row['bond']:8s} "
          f"LP {sol.alpha:.5f} step 2 {row['alpha']} [{row['status']}, {row['route']}] {row['time_s']:.1f} s "
          f"{row['lps']} LPs", flush=True)
    return row


def table(df: pd.DataFrame) -> str:
    m = machine()
    fmt = lambda v, f: "-" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, f)
    n_ok = int(df["verified"].sum())
    lines = [f"# Step 2 on the wall family (seed {SEED}; {m['cpus']} CPUs, Python {m['python']})", "",
             f"**{n_ok} of {len(df)} verified.** Members of scenes/generators/families.py; step 2 as "
             "`limit solve` runs it. 'spread' is the worst verified start's alpha over the best's, minus 1.", "",
             "| # | dim | blocks | mu | bond | openings | aspect | angle | LP alpha | step 2 alpha | route | "
             "time s | LPs | spread | reason |", "|" + " --- |" * 15]
    for _, r in df.iterrows():
        spread = (r["alpha_worst"] / r["alpha_best"] - 1) if (r.get("alpha_best") or 0) > 0 else None
        lines.append(f"| {r['index']} | {r['dim']} | {r['blocks']} | {r['mu']:g} | {r['bond']} | {r['openings']} | "
                     f"{r['aspect']:.2f} | {r['angle_deg']:g} | {r['alpha_lp']:.5f} | {fmt(r['alpha'], '.5f')} | "
                     f"{r['route']} | {r['time_s']:.1f} | {r['lps']} | {fmt(spread, '.2%')} | {r['reason']} |")
    return "\n".join(lines) + "\n"


def plot(df: pd.DataFrame, path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, dim in zip(axes, (2, 3)):
        d = df[df["dim"] == dim]
        for mu, g in d.groupby("mu"):
            ok = g[g["verified"]]
            bad = g[~g["verified"]]
            line = ax.plot(ok["blocks"], ok["time_s"], "o", label=f"mu {mu:g}")[0]
            ax.plot(bad["blocks"], bad["time_s"], "x", color=line.get_color(), ms=9)
        ax.set(xscale="log", yscale="log", xlabel="free blocks", title=f"{dim}D (x: not verified)")
        ax.grid(True, which="both", alpha=0.3)
        if d.empty:  # no member of this dimension in the run
            ax.text(0.5, 0.5, f"no {dim}D member run", transform=ax.transAxes, ha="center", va="center")
        else:
            ax.legend(fontsize=8)
    axes[0].set_ylabel("step 2 time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(indices=None) -> pd.DataFrame:
    out = out_dir()
    members = wall_family(SEED, COUNT, BLOCKS)
    if indices:
        members = [members[i] for i in indices]
    rows = []
    for sc in members:
        rows.append(one(sc))
        pd.DataFrame(rows).to_csv(out / "wall_family.csv", index=False)  # kept as it grows
    df = pd.DataFrame(rows)
    (out / "wall_family.md").write_text(table(df))
    plot(df, out / "wall_family.png")
    return df


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or None)
