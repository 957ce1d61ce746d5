"""Draw the screenshot of the report's interactive mechanism view for the docs (docs/img/report-view.png).

    .venv/bin/python scripts/draw_report_view.py [OUT.png]

A generated corner of two walls (limit build corner) loaded out of the plane of its first wall,
solved (LP, then step 2 where needed), drawn by :mod:`reports.view3d` as the report draws it, and
photographed by Debian's headless Chromium, the browser the test suite uses.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from reports import view3d  # noqa: E402
from reports.stages import la_options, run_la  # noqa: E402
from scenes import generators as G  # noqa: E402


def main(out: str = "docs/img/report-view.png") -> int:
    from limit.model.scene import load_scene

    data = G.wall_corner(length=2.0, length_b=1.6, height=1.2)
    data["name"] = "corner"
    data["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]  # out of the x wall's plane
    la = run_la(data, {**la_options(data), "global_max_free": 0, "iterative_max_free": 0})
    from reports import render

    page = render.render("view.html", title="", stamp="", wall_time=None, legend="", **view3d.script(),
                         views=view3d.divs(load_scene(data), la, {}, include_js=False))
    exe = shutil.which("chromium")
    if exe is None:
        print("chromium is not installed (scripts/bootstrap.sh installs it)", file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory() as tmp:
        html = Path(tmp) / "view.html"
        html.write_text(page)
        subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                        "--enable-unsafe-swiftshader", "--window-size=900,540", "--virtual-time-budget=8000",
                        f"--screenshot={Path(out).resolve()}", html.as_uri()], check=True, capture_output=True)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
