"""DEM pushover: run time against alpha error for the knobs, on closed-form cases.

Cases (rigid blocks, horizontal body force alpha x weight): one block b/h = 0.3
rocking (2D and 3D, alpha = 0.3), one block sliding (mu = 0.4 < b/h = 1,
alpha = 0.4), a stack of three blocks overturning as one (alpha = b/(3h) = 0.2).
Configurations: the defaults, then one knob changed at a time (stiffness pair,
damping, first load step, equilibrium tolerance, trial budget, bracket width).
Two YADE runs at a time (one per core). Writes bench/out/dem_knobs.csv (one row
per configuration and case) and bench/out/dem_knobs.png (log-log: total run time
of the cases against the worst |alpha error|, one point per configuration).

``target()`` (``python -m bench.dem_bench --target [--set knob=value ...]``,
not part of ``main``: it takes far longer than the grid) runs the 30-block
target: a slender running-bond wall (12 courses alternately of 2 and 3 blocks
(half blocks at the ends), L = 0.4, H = 0.175, mu = 1.2) -> bench/out/dem_target.csv.
Its reference is the project's limit analysis (:func:`limit.analysis.analyse`),
computed, not a hand value: the associative LP overturns the whole wall about
its toe, alpha = b/H = 0.8/2.1 = 0.381, but with friction (no dilatancy) the
NLP finds 0.346: the wall overturns about the toe of c0-1 and leaves the two
heel blocks c0-0, c1-0 behind (the head joints open). The DEM follows the
frictional physics, so the error is measured against the NLP alpha (the LP
one is recorded too).

The grid runs the default block model, the vertex-to-face model (its
stiffness pairs: the default (1e-5, 2.5e-6), a softer and a stiffer pair and
single stiffnesses, whose sphere radius is not extrapolated away). The knobs
other than the stiffness were chosen on the earlier Polyhedra model (damping
0.8 beat 0.5 and 0.9, trial_T = 10, step0 = 0.05, eq_tol = 1e-3, alpha_rtol =
0.005); the grid shows whether they still hold for the vertex model.
"""
from __future__ import annotations

import statistics
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import pandas as pd

from dem_validation import DEFAULTS, run_scene
from scenes import builders as B

from .common import machine, out_dir

CASES = {
    "rock-2d": (lambda: B.single_block(2, 0.3, 1.0, mu=0.8), 0.3),
    "rock-3d": (lambda: B.single_block(3, 0.3, 1.0, mu=0.8), 0.3),
    "slide-2d": (lambda: B.single_block(2, 1.0, 1.0, mu=0.4), 0.4),
    "stack-3-2d": (lambda: B.stack(3, 2, 0.3, 0.5, mu=0.8), 0.2),
}

CONFIGS = [
    ("defaults", {}),
    ("eps", {"eps": (4e-5, 1e-5)}),
    ("eps", {"eps": (2.5e-6, 6.25e-7)}),
    ("eps", {"eps": (1e-5,)}),
    ("eps", {"eps": (2.5e-6,)}),
    ("mass_quantile", {"mass_quantile": 0.5}),
    ("cfl", {"cfl": 2.0}),
    ("cfl", {"cfl": 2.0, "alpha_rtol": 0.01}),
    ("damping", {"damping": 0.5}),
    ("damping", {"damping": 0.9}),
    ("step0", {"step0": 0.02}),
    ("step0", {"step0": 0.15}),
    ("eq_tol", {"eq_tol": 1e-2}),
    ("eq_tol", {"eq_tol": 1e-4}),
    ("trial_T", {"trial_T": 5.0}),
    ("trial_T", {"trial_T": 20.0}),
    ("alpha_rtol", {"alpha_rtol": 0.01}),
    ("alpha_rtol", {"alpha_rtol": 0.0025}),
]

TARGET_NAME = "wall-12x2-2d"
TARGET_SCENE = lambda: B.running_bond_wall(12, 2, dim=2, mu=1.2)  # noqa: E731
#: knobs of the target run (see target()): the defaults
TARGET_KNOBS: dict = {}


def limit_alphas(scene_dict) -> dict:
    """LP and NLP (frictional) alpha of a scene, from the project's limit analysis."""
    from limit.analysis import analyse
    from limit.model.scene import load_scene

    res = analyse(load_scene(scene_dict), method="nlp").data
    return {"alpha_lp": res["lp"]["alpha"], "alpha_nlp": res["nlp"]["alpha"], "nlp_status": res["nlp"]["status"]}


def _label(knobs: dict) -> str:
    if not knobs:
        return "defaults"
    return ", ".join(f"{k}={'/'.join(f'{e:g}' for e in v) if isinstance(v, tuple) else f'{v:g}'}"
                     for k, v in knobs.items())


def _one(case: str, knobs: dict, timeout_s: float) -> dict:
    if case in CASES:
        build, expected = CASES[case]
    else:
        build, expected = TARGET_SCENE, limit_alphas(TARGET_SCENE())["alpha_nlp"]
    dem = run_scene(build(), timeout_s=timeout_s, **knobs)
    a = dem.get("alpha")
    return {"case": case, "expected": expected, "status": dem["status"], "alpha": a,
            "err": (a / expected - 1.0) if a is not None else float("nan"),
            "raw": "/".join(f"{r['alpha']:.5f}" for r in dem.get("runs", []) if r.get("alpha") is not None),
            "time_s": dem.get("time_s"), "steps": dem.get("steps"), "reason": dem.get("reason", "")}


def main(configs=CONFIGS, cases=tuple(CASES), workers=2, timeout_s=1800.0) -> pd.DataFrame:
    jobs = [(name, knobs, case) for name, knobs in configs for case in cases]
    rows = []
    with ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [(name, knobs, pool.submit(_one, case, knobs, timeout_s)) for name, knobs, case in jobs]
        for name, knobs, fut in futures:
            row = {"knob": name, "config": _label(knobs), **fut.result()}
            rows.append(row)
            print(f"dem {row['config']:28s} {row['case']:11s} alpha={row['alpha'] if row['alpha'] is None else round(row['alpha'], 5)}"
                  f" err={100 * row['err']:+.2f}% time={row['time_s']:.1f}s {row['reason']}", flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(out_dir() / "dem_knobs.csv", index=False)
    summary = df.groupby("config", sort=False).agg(
        total_s=("time_s", "sum"), worst_err=("err", lambda e: e.abs().max()),
        median_err=("err", lambda e: e.abs().median())).reset_index()
    summary.to_csv(out_dir() / "dem_knobs_summary.csv", index=False)
    print(summary.to_string(index=False))
    _plot(df, summary)
    return df


def _plot(df, summary):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    for case, g in df.groupby("case"):
        ax.scatter(g["time_s"], g["err"].abs().clip(lower=1e-5), s=12, alpha=0.35, label=f"{case} (one run)")
    ax.scatter(summary["total_s"], summary["worst_err"].clip(lower=1e-5), s=40, c="k", marker="D",
               label="configuration: total time, worst error")
    for _, r in summary.iterrows():
        ax.annotate(r["config"], (r["total_s"], max(r["worst_err"], 1e-5)), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(0.02, color="r", lw=0.8, ls="--", label="2% (test tolerance)")
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("|alpha / closed form - 1| (after extrapolation)")
    ax.set_title("DEM pushover: run time against alpha error (%s)" % ", ".join(CASES))
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(out_dir() / "dem_knobs.png", dpi=130)
    plt.close(fig)


def target(repeat=1, knobs=None, timeout_s=3600.0) -> pd.DataFrame:
    """The 30-block wall, ``repeat`` times (median time quoted), against the limit analysis."""
    knobs = dict(TARGET_KNOBS if knobs is None else knobs)
    scene = TARGET_SCENE()
    n_blocks = sum(1 for b in scene["blocks"] if not b.get("fixed"))
    la = limit_alphas(scene)
    rows = []
    for _ in range(repeat):
        t0 = time.monotonic()
        row = _one(TARGET_NAME, knobs, timeout_s)
        row["wall_s"] = time.monotonic() - t0
        row.update(config=_label(knobs), blocks=n_blocks, **la)
        row["err_lp"] = (row["alpha"] / la["alpha_lp"] - 1.0) if row["alpha"] is not None else float("nan")
        rows.append(row)
        print(f"dem target {TARGET_NAME} ({n_blocks} blocks, {row['config']}): alpha={row['alpha']} "
              f"NLP={la['alpha_nlp']:.5f} err={100 * row['err']:+.2f}% (LP={la['alpha_lp']:.5f}, "
              f"{100 * row['err_lp']:+.2f}%) raw={row['raw']} time={row['time_s']:.1f}s {row['reason']}", flush=True)
    df = pd.DataFrame(rows)
    path = out_dir() / "dem_target.csv"
    df.to_csv(path, mode="a", header=not path.exists(), index=False)
    print(f"median time {statistics.median(df['time_s']):.1f} s on {machine()}")
    return df


def _knobs_from_argv(argv) -> dict | None:
    """``--set knob=value`` (repeatable; eps as a/b) -> knobs; None when none is given."""
    knobs = {}
    for k, a in enumerate(argv):
        if a == "--set":
            name, value = argv[k + 1].split("=", 1)
            knobs[name] = tuple(float(e) for e in value.split("/")) if name == "eps" else float(value)
    return knobs if knobs or "--defaults" in argv else None


if __name__ == "__main__":
    if "--target" in sys.argv:
        target(knobs=_knobs_from_argv(sys.argv))
    else:
        main()
    print("defaults:", DEFAULTS)
