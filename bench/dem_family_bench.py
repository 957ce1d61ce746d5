"""Both DEM engines on the generated DEM family (scenes/generators/families.py, ``dem_member``),
structures the engines' knobs were not tuned on, each result judged against the limit analysis's
bracket [step 2, LP] (dem_validation/bracket.py, the engines' friction cone) as
``python -m dem_validation run`` judges it: a run suspect low is tried as a start of step 2, and
in 3D on point contacts (:func:`dem_validation.bracket.judge_with_start`).

Per member and engine: the alpha, its verdict (inside, suspect low, suspect high, unchecked,
or the run's status), the time, and LMGC90's alpha at each of its halved time steps. ``$DEM_FAMILY_COUNT`` members (default 8, every kind once) of
``$DEM_FAMILY_SEED`` (default 0); ``$DEM_FAMILY_TIMEOUT`` s per engine run (default 1800);
``$DEM_FAMILY_ENGINES`` a comma-separated subset of the engines (default all).
``python -m bench.dem_family_bench [INDEX...]`` runs only those members.
Writes bench/out/dem_family.csv (row by row) and dem_family.md (``dem_family-$DEM_FAMILY_TAG.*`` when the tag is set).
"""
from __future__ import annotations

import os
import sys
import time

import pandas as pd

from dem_validation import engines
from dem_validation.api import run_scene
from dem_validation.bracket import judge_with_start, limit_analysis
from limit.model.scene import load_scene
from reports.table import dt_text
from scenes.generators.families import dem_family

from .common import machine, out_dir

SEED = int(os.environ.get("DEM_FAMILY_SEED", 0))
COUNT = int(os.environ.get("DEM_FAMILY_COUNT", 8))
TIMEOUT = float(os.environ.get("DEM_FAMILY_TIMEOUT", 1800))
TAG = os.environ.get("DEM_FAMILY_TAG", "")
STEM = f"dem_family-{TAG}" if TAG else "dem_family"
ENGINES = tuple(e for e in os.environ.get("DEM_FAMILY_ENGINES", ",".join(engines.names())).split(",") if e)
for _e in ENGINES:
    engines.get(_e)  # ValueError naming the known engines


def rows(scene_dict: dict) -> list[dict]:
    """One row per engine of one member."""
    f = scene_dict["meta"]["family"]
    scene = load_scene(scene_dict)
    t = time.perf_counter()
    la = limit_analysis(scene)
    la_s = time.perf_counter() - t
    out = []
    for engine in ENGINES:
        dem = run_scene(scene, engine=engine, timeout_s=TIMEOUT)
        br = judge_with_start(scene, dem, la)  # as `python -m dem_validation run` judges it
        verdict = (br["verdict"] if br["verdict"] != "suspect" else f"suspect {br['side']}") \
            if dem.get("status") == "collapsed" else dem.get("status")
        out.append({"index": f["index"], "kind": f["kind"], "dim": f["dim"], "free": len(scene.free), "mu": f["mu"],
                    "fric_alpha": la["fric_alpha"], "lp_alpha": la["lp_alpha"], "la_s": la_s, "engine": engine,
                    "alpha": dem.get("alpha"), "verdict": verdict, "time_s": dem.get("time_s"),
                    "dt": dt_text(dem),
                    "reason": (br.get("reason") if br["verdict"] == "suspect" else dem.get("reason")) or ""})
        r = out[-1]
        print(f"dem-family {r['index']:2d} {r['kind']:28s} {engine:6s} alpha {r['alpha']} [{verdict}] "
              f"bracket [{la['fric_alpha']}, {la['lp_alpha']}] {r['time_s'] or 0:.0f} s", flush=True)
    return out


def table(df: pd.DataFrame) -> str:
    m = machine()
    fmt = lambda v, f: "-" if v is None or pd.isna(v) else format(v, f)  # noqa: E731
    lines = [f"# Both engines on the DEM family (seed {SEED}; {m['cpus']} CPUs, Python {m['python']})", ""]
    for engine in ENGINES:
        d = df[df["engine"] == engine]
        lines.append(f"- {engine}: {int((d['verdict'] == 'inside').sum())} of {len(d)} inside the bracket "
                     f"[step 2, LP] (1 % slack); suspect: {int(d['verdict'].astype(str).str.startswith('suspect').sum())}")
    lines += ["", "| # | kind | dim | free | mu | step 2 | LP | engine | alpha | verdict | time s | time steps | reason |",
              "|" + " --- |" * 13]
    for _, r in df.iterrows():
        lines.append(f"| {r['index']} | {r['kind']} | {r['dim']} | {r['free']} | {r['mu']:g} | "
                     f"{fmt(r['fric_alpha'], '.5f')} | {fmt(r['lp_alpha'], '.5f')} | {r['engine']} | "
                     f"{fmt(r['alpha'], '.5f')} | {r['verdict']} | {fmt(r['time_s'], '.0f')} | {r.get('dt') or ''} | "
                     f"{r['reason'][:160]} |")
    return "\n".join(lines) + "\n"


def main(indices=None) -> pd.DataFrame:
    out = out_dir()
    members = dem_family(SEED, COUNT)
    if indices:
        members = [members[i] for i in indices]
    acc = []
    for sc in members:
        acc += rows(sc)
        pd.DataFrame(acc).to_csv(out / f"{STEM}.csv", index=False)  # kept as it grows
    df = pd.DataFrame(acc)
    (out / f"{STEM}.md").write_text(table(df))
    return df


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or None)
