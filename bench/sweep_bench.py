"""The worst load direction of the paper's Fig. 6 intersecting walls: alpha(theta) every
5 degrees over 360 (LP per direction, on Dask workers when that pays), step 2 at the minimum; then
the frictional sweep (step 2 in every direction, with the neighbour pass). Writes bench/out/sweep.md,
sweep.csv and the polar plots sweep-fig6.png and sweep-fig6-frictional.png."""
from __future__ import annotations

import json
from pathlib import Path

import pandas as pd

from .common import machine, out_dir

SCENE = Path(__file__).resolve().parent.parent / "scenes" / "catalog" / "paper-fig6-intersecting-walls-3d.json"


def main() -> None:
    from limit.direction_sweep import sweep
    from reports.plots import direction_polar

    out = out_dir()
    data = json.loads(SCENE.read_text())
    res = sweep(data, 5.0, progress=lambda k, n: print(f"  {k}/{n} directions", end="\r", flush=True))
    fr = sweep(data, 5.0, every=True, progress=lambda k, n: print(f"  {k}/{n} directions, step 2", end="\r", flush=True))
    direction_polar(fr, out / "sweep-fig6-frictional.png", "Fig. 6 intersecting walls, step 2 in every direction")
    passes = fr.get("neighbour_passes") or {}
    pd.DataFrame({"theta_deg": res["theta"], "lp_alpha": res["alpha"], "status": res["status"]}).to_csv(
        out / "sweep.csv", index=False)
    direction_polar(res, out / "sweep-fig6.png", "Fig. 6 intersecting walls")
    nlp = (res.get("min_nlp") or {}).get("nlp") or {}
    at0 = res["alpha"][0]
    text = (f"# Worst load direction, Fig. 6 intersecting walls ({machine()})\n\n"
            f"72 directions every 5 degrees (0 = the scene's +x), LP per direction on {res['jobs']} process(es) (Dask only when it saves more than its start-up).\n\n"
            f"| quantity | value |\n| --- | --- |\n"
            f"| LP alpha along +x (the catalog's direction) | {at0:.5g} |\n"
            f"| minimum LP alpha | {res['min_alpha']:.5g} at {res['min_theta']:g} deg |\n"
            f"| frictional step 2 there | {nlp.get('alpha')} ({nlp.get('status')}) |\n"
            f"| wall clock, whole sweep | {res['time_s']:.1f} s |\n"
            f"| LP time summed over directions | {res['lp_time_s']:.1f} s |\n"
            f"| frictional minimum (step 2 in every direction) | {fr.get('min_alpha_frictional')} at "
            f"{fr.get('min_theta_frictional')} deg |\n"
            f"| frictional alpha along +x | {fr['alpha_frictional'][0]:.6g} |\n"
            f"| directions lowered by the neighbour pass | {len(passes.get('improved', {}))} of 72, "
            f"{passes.get('rounds')} round(s), {passes.get('time_s', 0.0):.1f} s |\n"
            f"| wall clock, frictional sweep | {fr['time_s']:.1f} s |\n\n"
            "![polar plot](sweep-fig6.png) ![frictional](sweep-fig6-frictional.png)\n")
    (out / "sweep.md").write_text(text)
    print(text)
