"""NLP (step 2) benchmark: time, the gap to the global (mixed-integer) optimum, restart strategies.

1. Walls of 10 to 1,000 blocks (2D running bond, 0.4 x 0.3 m blocks, mu = 0.9, a
   horizontal body force, where rocking and sliding combine): LP and NLP time,
   alpha_lp, alpha_nlp and, up to 20 blocks, the MILP's global optimum (60 s limit).
2. Which restarts matter: small walls whose global optimum the MILP proves, solved
   with the LP start alone and with each restart strategy added.
3. scipy's trust-constr (sparse, with the exact Hessian of the complementarity) on
   the same formulation, for comparison with the successive LP.
4. Domes of rings of voussoirs (scenes.generators.dome, 24 sliding faces): which stage of
   step 2's plan verifies first (the LP's point and its restarts, the LP's simplex vertex, the
   coarser friction polygon), and the runs that verify.
5. The global MILP's bound tightening (limit.solve.milp._bounds, one warm-started HiGHS model per
   family of per-face LPs) side by side with the same LPs solved one by one
   (tests/test_nlp.py::cold_bounds) on small catalog scenes: the times, their ratio, and the
   largest difference of a bound.
Writes bench/out/nlp.csv, nlp_strategies.csv, nlp_solvers.csv, nlp_domes.csv, nlp_milp.csv,
nlp.png and nlp_summary.md.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pandas as pd
import scipy.sparse as sp
from scipy.optimize import LinearConstraint, NonlinearConstraint, minimize

from limit import step2
from limit.settings import DEFAULT
from limit.solve import milp, nlp, nlp_starts
from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.solve.nlp_problem import build
from limit.model.scene import load_scene
from scenes import builders as B
from scenes import generators as G

from .common import machine, out_dir

SIZES = (10, 30, 60, 100, 300, 1000)
MILP_MAX_BLOCKS = 20
SMALL_WALLS = [(3, 3, 0.4, 0.4), (3, 3, 0.2, 0.4), (3, 2, 0.4, 0.3), (2, 2, 0.4, 0.4)]
MUS = (0.6, 0.9, 1.2)
#: (meridians, rings) of the domes of :func:`domes_part`
DOMES = ((8, 2), (12, 2), (12, 3), (16, 3), (16, 4))
#: catalog scenes of :func:`milp_part`
MILP_SCENES = ("portal-3d", "wall-3x3-opening-2d", "wall-3x3-3d", "paper-fig3-opus-poligonale-25-2d",
               "wall-out-of-plane-3d")


def wall(n, mu=0.9):
    courses = max(2, int(round(math.sqrt(n))))
    per = max(2, int(round(n / courses)))
    return B.running_bond_wall(courses, per, dim=2, L=0.4, H=0.3, mu=mu)


def solve_trust_constr(N, z0, maxiter=3000):
    """min alpha, linear constraints sparse, complementarity as an equality with its exact Hessian."""
    n = N.n
    lo, hi = N.bounds()
    lo[N.ia] = 0.0
    e = np.zeros(n)
    e[N.ia] = 1.0
    Yh = N.P.Yh
    H = sp.lil_matrix((n, n))
    H[N.sx, N.sl] = -Yh.T
    H[N.sl, N.sx] = -Yh
    H = H.tocsr()
    cons = [LinearConstraint(N.Aeq, N.beq, N.beq), LinearConstraint(N.Yx, -np.inf, 0.0),
            NonlinearConstraint(lambda z: np.array([N.comp(z)]), 0.0, 0.0,
                                jac=lambda z: sp.csr_matrix(N.comp_grad(z)), hess=lambda z, v: v[0] * H)]
    from scipy.optimize import Bounds

    res = minimize(lambda z: z[N.ia], z0, jac=lambda z: e, hess=lambda z: sp.csr_matrix((n, n)),
                   method="trust-constr", constraints=cons, bounds=Bounds(lo, hi),
                   options={"maxiter": maxiter, "gtol": 1e-9, "xtol": 1e-12, "verbose": 0})
    return res.x, res.message


def sizes_part():
    rows = []
    for n in SIZES:
        d = wall(n)
        scene = load_scene(d)
        t0 = time.perf_counter()
        P = assemble(scene)
        sol, _, _ = solve_lp(P)
        t_lp = time.perf_counter() - t0
        t1 = time.perf_counter()
        part = step2.step2(P, sol, method="nlp", global_check=scene.n_blocks - 1 <= MILP_MAX_BLOCKS,
                         global_time_limit=60.0)
        t_nlp = time.perf_counter() - t1 - (part.get("global", {}).get("time_s") or 0.0)
        g = part.get("global", {})
        row = {"n_blocks": scene.n_blocks, "n_interfaces": len(P.I), "n_unknowns": build(P).n,
               "alpha_lp": sol.alpha, "alpha_nlp": part.get("alpha"), "nlp_status": part["status"],
               "lp_s": t_lp, "nlp_s": t_nlp, "runs": len(part.get("runs", [])),
               "runs_verified": sum(bool(r.get("verified")) for r in part.get("runs", [])),
               "best_start": part.get("start"), "milp_status": g.get("status"), "alpha_milp": g.get("alpha"),
               "milp_bound": g.get("bound"), "milp_s": g.get("time_s"), "gap_to_milp": g.get("gap")}
        rows.append(row)
        print(f"nlp {scene.n_blocks:5d} blocks: lp {sol.alpha:.5f} ({t_lp:.2f} s)  nlp {row['alpha_nlp']} "
              f"[{part['status']}] ({t_nlp:.2f} s)  milp {g.get('alpha')} [{g.get('status')}]", flush=True)
    return pd.DataFrame(rows)


def strategies_part():
    rows = []
    variants = {"LP start only": ((), ), "+ penalty restarts": (("penalty",),),
                "+ random restarts": (("penalty", "random"),), "+ reduced friction (default)": (step2.ALL_STRATEGIES,)}
    for (c, k, L, H) in SMALL_WALLS:
        for mu in MUS:
            P = assemble(load_scene(B.running_bond_wall(c, k, dim=2, L=L, H=H, mu=mu)))
            sol, _, _ = solve_lp(P)
            found = {}
            for label, (strat,) in variants.items():
                t0 = time.perf_counter()
                out = step2.run(P, sol, restarts=bool(strat), strategies=strat)
                found[label] = (out.alpha if out.ok else None, time.perf_counter() - t0)
            ub = min([a for a, _ in found.values() if a is not None] + [sol.alpha])
            g = milp.global_minimum(P, ub, time_limit=120)
            for label, (a, t) in found.items():
                rows.append({"wall": f"{c}x{k} {L}x{H} m", "mu": mu, "strategy": label, "alpha_lp": sol.alpha,
                             "alpha_nlp": a, "time_s": t, "alpha_milp": g.alpha, "milp_status": g.status,
                             "at_global": a is not None and g.alpha is not None
                             and abs(a - g.alpha) <= 1e-6 * max(1.0, g.alpha)})
            print(f"strategies {c}x{k} mu {mu}: milp {g.alpha} " +
                  " ".join(f"{lb.split()[1] if ' ' in lb else lb}={a}" for lb, (a, _) in found.items()), flush=True)
    return pd.DataFrame(rows)


def _stage(start: str) -> str:
    """The stage of step2.run's plan that a run's start label belongs to."""
    return "vertex" if start == "lp-vertex" else "coarse" if start.startswith("coarse") else "plan"


def domes_part():
    rows = []
    for m, k in DOMES:
        P = assemble(load_scene(G.dome(meridians=m, rings=k)))
        sol, _, _ = solve_lp(P)
        t0 = time.perf_counter()
        out = step2.run(P, sol)  # with the default budget, as limit solve runs it
        t = time.perf_counter() - t0
        runs = [r for r in out.runs if "not_run" not in r]
        ok = [r for r in runs if r.get("verified")]
        rows.append({"dome": f"{m} x {k}", "blocks": P.scene.n_blocks, "unknowns": out.N.n, "lp_solver": sol.solver,
                     "alpha_lp": sol.alpha, "alpha": out.alpha if out.ok else None, "verified": out.ok,
                     "stage": _stage(out.start) if out.ok else "", "runs": len(runs), "runs_verified": len(ok),
                     "stages_run": ", ".join(dict.fromkeys(_stage(r.get("start", "")) for r in runs)), "time_s": t})
        print(f"dome {m}x{k}: lp {sol.alpha:.5f} step 2 {rows[-1]['alpha']} from {rows[-1]['stage']} "
              f"({len(ok)}/{len(runs)} runs verified, {t:.1f} s)", flush=True)
    return pd.DataFrame(rows)


def milp_part():
    from pathlib import Path

    from tests.test_nlp import cold_bounds

    rows = []
    for name in MILP_SCENES:
        P = assemble(load_scene(Path(__file__).parents[1] / "scenes" / "catalog" / f"{name}.json"))
        sol, _, _ = solve_lp(P)
        N = build(P)
        ub = sol.alpha * (1 + 1e-9)
        t0 = time.perf_counter()
        S, L = milp._bounds(N, P, ub, float("inf"))
        t_warm = time.perf_counter() - t0
        t0 = time.perf_counter()
        S0, L0 = cold_bounds(N, P, ub)
        t_cold = time.perf_counter() - t0
        diff = max(float(np.max(np.abs(np.where(np.isfinite(a0), a - a0, 0.0)), initial=0.0)) for a, a0 in ((S, S0), (L, L0)))
        rows.append({"scene": name, "faces": P.model.n_faces, "warm_s": t_warm, "cold_s": t_cold,
                     "ratio": t_cold / t_warm, "max_diff": diff})
        print(f"milp bounds {name}: {t_warm:.2f} s against {t_cold:.2f} s one by one ({t_cold / t_warm:.1f}x), "
              f"largest difference {diff:.1e}", flush=True)
    return pd.DataFrame(rows)


def trust_constr_part():
    rows = []
    for n in (10, 30):
        P = assemble(load_scene(wall(n)))
        sol, _, _ = solve_lp(P)
        N = build(P)
        z0, _ = nlp.phase1(N, nlp_starts.lp_start(N, sol), "highs")
        for label, fn in (("trust-constr", lambda: solve_trust_constr(N, z0)),
                          ("slsqp", lambda: nlp.solve_slsqp(N, z0)),
                          ("sla", lambda: nlp.solve_sla(N, z0, "highs"))):
            if label == "slsqp" and N.n > DEFAULT.slsqp_max_vars:
                continue
            t0 = time.perf_counter()
            z, msg = fn()
            t = time.perf_counter() - t0
            ok, _, why = nlp.check(N, z, sol.alpha)
            rows.append({"n_blocks": P.scene.n_blocks, "n_unknowns": N.n, "solver": label, "alpha": float(z[N.ia]),
                         "verified_unpolished": ok, "time_s": t, "message": str(msg)[:80]})
            print(f"single solver {label:12s} {P.scene.n_blocks} blocks: alpha {z[N.ia]:.5f} verified {ok} "
                  f"{t:.2f} s {str(msg)[:60]}", flush=True)
    return pd.DataFrame(rows)


def main():
    out = out_dir()
    df = sizes_part()
    df.to_csv(out / "nlp.csv", index=False)
    st = strategies_part()
    st.to_csv(out / "nlp_strategies.csv", index=False)
    tc = trust_constr_part()
    tc.to_csv(out / "nlp_solvers.csv", index=False)
    dm = domes_part()
    dm.to_csv(out / "nlp_domes.csv", index=False)
    mp = milp_part()
    mp.to_csv(out / "nlp_milp.csv", index=False)
    plot(df, out / "nlp.png")
    summary(df, st, tc, dm, mp, out / "nlp_summary.md")


def plot(df, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    axes[0].loglog(df.n_blocks, df.lp_s, "o-", label="LP (step 1)")
    axes[0].loglog(df.n_blocks, df.nlp_s, "s-", label="NLP (step 2, all restarts)")
    axes[0].set_xlabel("blocks")
    axes[0].set_ylabel("seconds")
    axes[0].set_title("2D walls, mu = 0.9")
    axes[0].grid(True, which="both", alpha=0.3)
    axes[0].legend()
    axes[1].plot(df.n_blocks, df.alpha_lp, "o-", label="LP (associative)")
    axes[1].plot(df.n_blocks, df.alpha_nlp, "s-", label="NLP (frictional)")
    m = df.dropna(subset=["alpha_milp"])
    axes[1].plot(m.n_blocks, m.alpha_milp, "k*", ms=12, label="MILP global")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("blocks")
    axes[1].set_ylabel("alpha")
    axes[1].grid(True, alpha=0.3)
    axes[1].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary(df, st, tc, dm, mp, path):
    m = machine()
    lines = [f"# NLP benchmark ({m['cpus']} CPUs, Python {m['python']})", "",
             "| blocks | interfaces | unknowns | alpha LP | alpha NLP | NLP status | LP s | NLP s | runs ok | "
             "MILP alpha | MILP status | gap NLP-MILP |", "| " + " --- |" * 12]
    for _, r in df.iterrows():
        fmt = lambda v, f: "" if v is None or (isinstance(v, float) and np.isnan(v)) else format(v, f)
        lines.append(f"| {r.n_blocks} | {r.n_interfaces} | {r.n_unknowns} | {r.alpha_lp:.5f} | "
                     f"{fmt(r.alpha_nlp, '.5f')} | {r.nlp_status} | {r.lp_s:.2f} | {r.nlp_s:.2f} | "
                     f"{r.runs_verified}/{r.runs} | {fmt(r.alpha_milp, '.5f')} | {r.milp_status or ''} | "
                     f"{fmt(r.gap_to_milp, '.1e')} |")
    lines += ["", "## Restart strategies (small walls, global optimum by MILP)", "",
              "| strategy | at the global optimum | median time s |", "| --- | --- | --- |"]
    for label, g in st.groupby("strategy", sort=False):
        lines.append(f"| {label} | {int(g.at_global.sum())}/{len(g)} | {g.time_s.median():.2f} |")
    lines += ["", "## Single solvers from the LP start (before polish)", "",
              "| blocks | unknowns | solver | alpha | verified | s |", "| --- | --- | --- | --- | --- | --- |"]
    for _, r in tc.iterrows():
        lines.append(f"| {r.n_blocks} | {r.n_unknowns} | {r.solver} | {r.alpha:.5f} | {r.verified_unpolished} | "
                     f"{r.time_s:.2f} |")
    lines += ["", "## Domes: the stage of step 2's plan that verifies first", "",
              "| dome (meridians x rings) | blocks | unknowns | alpha LP | alpha step 2 | from | runs ok | stages run | s |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for _, r in dm.iterrows():
        a = "not verified" if r.alpha is None or r.alpha != r.alpha else f"{r.alpha:.6f}"
        lines.append(f"| {r.dome} | {r.blocks} | {r.unknowns} | {r.alpha_lp:.6f} | {a} | {r.stage} | "
                     f"{r.runs_verified}/{r.runs} | {r.stages_run} | {r.time_s:.1f} |")
    lines += ["", "## The global MILP's bound tightening: one warm-started model against LPs one by one", "",
              "| scene | faces | warm s | one by one s | ratio | largest difference |", "| --- | --- | --- | --- | --- | --- |"]
    for _, r in mp.iterrows():
        lines.append(f"| {r.scene} | {r.faces} | {r.warm_s:.2f} | {r.cold_s:.2f} | {r.ratio:.1f} | {r.max_diff:.1e} |")
    path.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
