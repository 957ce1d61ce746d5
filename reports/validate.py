"""``make validate``: every catalog scene through every stage, then the report.

Stages so far: scene check and interface detection (``limit info``).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from limit import jsonio
from limit.errors import SceneError
from limit.info import scene_info
from limit.scene import load_scene
from scenes.catalog import catalog_files

OUT = Path(__file__).resolve().parent / "out"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m reports.validate")
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--jobs", type=int, default=None)
    args = ap.parse_args(argv)
    out = Path(args.out)
    rows = []
    for path in catalog_files():
        t0 = time.perf_counter()
        try:
            info = scene_info(load_scene(path))
            info["status"] = "ok"
        except SceneError as exc:
            info = {"name": path.stem, "status": f"rejected: {exc}"}
        info["time_s"] = time.perf_counter() - t0
        rows.append(info)
        print(f"{path.stem}: {info['status']}", flush=True)
    jsonio.write_json(out / "results.json", rows)
    lines = ["# Catalog", "", "| scene | dim | blocks | interfaces | status |", "| --- | --- | --- | --- | --- |"]
    lines += [f"| {r['name']} | {r.get('dim', '')} | {r.get('n_blocks', '')} | {r.get('n_interfaces', '')} | {r['status']} |"
              for r in rows]
    (out / "index.md").write_text("\n".join(lines) + "\n")
    print(f"report: {out / 'index.md'}")
    return 0 if all(r["status"] == "ok" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
