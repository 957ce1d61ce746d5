"""LP (step 1) benchmark: assembly, cvxpy compile and solve time, accuracy and conditioning.

Running-bond walls (2D: 10 to 10,000 blocks; 3D: 10 to 3,000) under a horizontal
body force, for each solver. Accuracy: every static solution is statically
admissible (checked), so its alpha is a lower bound; the error of a run is its
distance below the best verified alpha of that wall. Writes bench/out/lp.csv,
lp.png and lp_summary.md.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pandas as pd

from limit.settings import DEFAULT
from limit.solve import lp as lpmod, verify
from limit.model.assemble import assemble
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene
from scenes import builders as B

from .common import machine, out_dir

SIZES = {2: (10, 100, 1000, 3000, 10000), 3: (10, 100, 1000, 3000)}
#: (label, solver, option overrides, largest wall in blocks per dimension)
VARIANTS = [
    ("auto", "auto", None, {2: 10**6, 3: 10**6}),
    ("ipm", "ipm", None, {2: 10**6, 3: 10**6}),
    ("ipm no correctors", "ipm", {"correctors": 0}, {2: 10**6, 3: 10**6}),
    ("clarabel", "clarabel", None, {2: 10**6, 3: 10**6}),
    ("clarabel tol 1e-8", "clarabel", {"tol_gap_abs": 1e-8, "tol_gap_rel": 1e-8, "tol_feas": 1e-8,
                                        "tol_ktratio": 1e-6}, {2: 10**6, 3: 10**6}),
    ("clarabel auto-kkt", "clarabel", {"direct_solve_method": "auto"}, {2: 1000, 3: 1000}),
    ("ecos", "ecos", None, {2: 3000, 3: 1000}),
    ("highs-ipm", "highs-ipm", None, {2: 3000, 3: 1000}),
    ("highs simplex", "highs", None, {2: 1000, 3: 100}),
]


def wall(dim, n):
    side = max(2, int(round(math.sqrt(n))))
    return B.running_bond_wall(side, side, dim=dim, mu=0.65)


def conditioning(P) -> dict:
    """Spread of the scaled matrices' column and row norms; 2-norm condition of Eh when small."""
    import scipy.sparse.linalg as spla

    coln = np.sqrt(np.asarray(P.Eh.multiply(P.Eh).sum(axis=0)).ravel())
    rown = np.sqrt(np.asarray(P.Eh.multiply(P.Eh).sum(axis=1)).ravel())
    out = {"Eh_col_spread": float(coln.max() / max(coln[coln > 0].min(), 1e-300)),
           "Eh_row_spread": float(rown.max() / max(rown[rown > 0].min(), 1e-300)),
           "Dx_spread": float(P.Dx.max() / P.Dx.min())}
    if P.Eh.shape[0] <= 3000:
        s = np.linalg.svd(P.Eh.toarray(), compute_uv=False)
        out["Eh_cond"] = float(s.max() / s[s > 0].min())
    else:
        out["Eh_cond"] = float("nan")
    return out


def main() -> pd.DataFrame:
    rows = []
    for dim, sizes in SIZES.items():
        for n in sizes:
            d = wall(dim, n)
            t0 = time.perf_counter()
            scene = load_scene(d)
            t_load = time.perf_counter() - t0
            I = find_interfaces(scene)
            P = assemble(scene, interfaces=I)
            P.timings["interfaces_s"] = time.perf_counter() - t0 - t_load - P.timings["assembly_s"]
            cond = conditioning(P)
            for label, solver, over, limit in VARIANTS:
                if scene.n_blocks > limit[dim] * 1.1:
                    continue
                sol = lpmod.static_lp(P, solver, over)
                ok = False
                if sol.alpha is not None:
                    ok, res, why = verify.check_lp(P, sol)
                row = {"dim": dim, "n_blocks": scene.n_blocks, "n_interfaces": len(I), "n_x": P.model.n_x,
                       "n_faces": P.model.n_faces, "solver": label, "status": sol.cvxpy_status, "verified": ok,
                       "alpha": sol.alpha, "load_s": t_load, "interfaces_s": P.timings["interfaces_s"],
                       "assembly_s": P.timings["assembly_s"], "compile_s": sol.timings.get("compile_s"),
                       "solve_s": sol.timings.get("solve_s"), **cond}
                row["total_s"] = row["load_s"] + row["interfaces_s"] + row["assembly_s"] + sol.timings["solver_total_s"]
                rows.append(row)
                print(f"lp {dim}D {scene.n_blocks:6d} blocks {label:18s} {sol.cvxpy_status:18s} "
                      f"alpha={sol.alpha if sol.alpha is None else f'{sol.alpha:.8f}'} total {row['total_s']:.2f} s "
                      f"(solve {row['solve_s']:.2f} s)", flush=True)
    df = pd.DataFrame(rows)
    ref = df[df.verified].groupby(["dim", "n_blocks"]).alpha.max().rename("alpha_ref")
    df = df.join(ref, on=["dim", "n_blocks"])
    df["rel_error"] = (df.alpha_ref - df.alpha) / df.alpha_ref
    out = out_dir()
    df.to_csv(out / "lp.csv", index=False)
    plot(df, out / "lp.png")
    summary(df, out / "lp_summary.md")
    return df


def plot(df, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, dim in zip(axes[:2], (2, 3)):
        for label, g in df[df.dim == dim].groupby("solver"):
            ax.loglog(g.n_blocks, g.total_s, "o-", label=label)
        sub = df[(df.dim == dim) & (df.solver == "auto")]
        ax.loglog(sub.n_blocks, sub.load_s + sub.interfaces_s + sub.assembly_s + sub.compile_s, "k--",
                  label="auto: load + assembly + compile (ipm: its set-up)")
        ax.set_title(f"{dim}D running-bond walls: LP time")
        ax.set_xlabel("blocks")
        ax.set_ylabel("seconds")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    ax = axes[2]
    for label, g in df[df.verified].groupby("solver"):
        ax.loglog(g.total_s, np.maximum(g.rel_error, 1e-12), "o", label=label)
    ax.set_title("accuracy: alpha below the best verified")
    ax.set_xlabel("total seconds")
    ax.set_ylabel("relative error (floor 1e-12)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary(df, path):
    m = machine()
    lines = [f"# LP benchmark ({m['cpus']} CPUs, Python {m['python']})", "",
             f"Default solver 'auto': the structured interior point method (limit/solve/ipm.py) from "
             f"{DEFAULT.lp_ipm_min_dof} block unknowns on, Clarabel (qdldl, tolerances 1e-10) below.", ""]
    for dim, n in ((2, 10000), (3, 3000)):
        r = df[(df.dim == dim) & (df.solver == "auto")]
        r = r.iloc[(r.n_blocks - n).abs().argsort()[:1]]
        if len(r):
            r = r.iloc[0]
            setup = r.load_s + r.interfaces_s + r.assembly_s + r.compile_s
            lines.append(f"- {dim}D wall of {r.n_blocks} blocks: total {r.total_s:.1f} s "
                         f"(load {r.load_s:.2f}, interfaces {r.interfaces_s:.2f}, assembly {r.assembly_s:.2f}, "
                         f"compile {r.compile_s:.2f}, solve {r.solve_s:.1f}); set-up share {setup / r.total_s:.0%}; "
                         f"relative error {r.rel_error:.1e}")
    lines += ["", "Speed of ipm against Clarabel (total time, same wall; both verified):", ""]
    for (dim, n), g in df.groupby(["dim", "n_blocks"]):
        t = g.set_index("solver")
        if {"ipm", "clarabel"} <= set(t.index) and t.loc["ipm", "verified"] and t.loc["clarabel", "verified"]:
            lines.append(f"- {dim}D {n} blocks: clarabel {t.loc['clarabel', 'total_s']:.2f} s, ipm "
                         f"{t.loc['ipm', 'total_s']:.2f} s (x{t.loc['clarabel', 'total_s'] / t.loc['ipm', 'total_s']:.1f}); "
                         f"alpha differs by {abs(t.loc['ipm', 'alpha'] - t.loc['clarabel', 'alpha']) / t.loc['clarabel', 'alpha']:.1e}")
    lines += ["", "ipm's solve with and without Gondzio's centrality correctors (same wall, same run):", ""]
    for (dim, n), g in df.groupby(["dim", "n_blocks"]):
        t = g.set_index("solver")
        if {"ipm", "ipm no correctors"} <= set(t.index):
            lines.append(f"- {dim}D {n} blocks: {t.loc['ipm no correctors', 'solve_s']:.2f} s without, "
                         f"{t.loc['ipm', 'solve_s']:.2f} s with "
                         f"(x{t.loc['ipm no correctors', 'solve_s'] / t.loc['ipm', 'solve_s']:.2f})")
    lines += ["", "| dim | blocks | solver | status | verified | alpha | rel. error | total s | solve s |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for _, r in df.iterrows():
        a = "" if pd.isna(r.alpha) else f"{r.alpha:.8f}"
        e = "" if pd.isna(r.rel_error) else f"{r.rel_error:.1e}"
        lines.append(f"| {r.dim} | {r.n_blocks} | {r.solver} | {r.status} | {r.verified} | {a} | {e} | "
                     f"{r.total_s:.2f} | {r.solve_s:.2f} |")
    path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
