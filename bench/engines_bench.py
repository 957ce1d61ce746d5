"""The catalog, limit analysis against YADE against LMGC90, with times: runs ``make
validate``'s stages with LMGC90 on every scene (``--lmgc-all``: the costliest nine, about
890 s of LMGC90 in all, are left out of the 30-minute default validation; cached results
are reused, so after ``make validate`` this costs those runs only) and writes
bench/out/engines.md and engines.csv."""
from __future__ import annotations

from .common import machine, out_dir


def main() -> None:
    from reports import table
    from reports.validate import main as validate

    out = out_dir()
    code = validate(["--out", str(out / "validate"), "--no-progress", "--lmgc-all"])
    if code != 0:
        raise SystemExit(f"validate ended with status {code}")
    import pandas as pd

    df = pd.read_parquet(out / "validate" / "results.parquet")
    df.to_csv(out / "engines.csv", index=False)
    text = (f"Catalog: limit analysis against YADE (vertex model, extrapolated to rigid contacts) and LMGC90 "
            f"(rigid blocks), {machine()}; times are each stage's wall clock with two stages running at once. "
            f"The LA's frictional value is the NLP's (or the MILP's where lower); the 24-face cone is the LA "
            f"with a near-circular friction cone (3D only).\n\n" + table.engines_markdown(df))
    (out / "engines.md").write_text(text)
    print(text)
