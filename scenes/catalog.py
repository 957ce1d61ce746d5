"""The scene catalog: every entry built by :mod:`scenes.builders` and kept as JSON
in ``scenes/catalog/``. ``python -m scenes.catalog`` rewrites the files;
``python -m scenes.catalog --check`` fails if a file differs from its builder.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from . import builders as B

CATALOG_DIR = Path(__file__).resolve().parent / "catalog"


def entries() -> dict:
    """name -> scene dict, in report order."""
    out = {}

    def add(d):
        assert d["name"] not in out, d["name"]
        out[d["name"]] = d

    add(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6, name="block-rocking-2d",
                       expected={"alpha": 0.3, "rtol": 1e-6, "source": "analytic: overturning about the toe, alpha = b/h"}))
    add(B.single_block(dim=3, b=0.3, h=1.0, t=0.5, mu=0.6, name="block-rocking-3d",
                       expected={"alpha": 0.3, "rtol": 1e-6, "source": "analytic: overturning about the toe, alpha = b/h"}))
    add(B.single_block(dim=2, b=1.0, h=0.5, mu=0.4, name="block-sliding-2d",
                       expected={"alpha": 0.4, "rtol": 1e-6, "source": "analytic: sliding, alpha = mu (b/h = 2 > mu)"}))
    add(B.single_block(dim=3, b=1.0, h=0.5, t=1.0, mu=0.4, name="block-sliding-3d",
                       expected={"alpha": 0.4, "rtol": 1e-6, "source": "analytic: sliding, alpha = mu (b/h = 2 > mu)"}))
    add(B.stack(3, dim=2, b=0.3, h=0.4, mu=0.8, name="stack-3-2d",
                expected={"alpha": 0.3 / 1.2, "rtol": 1e-6,
                          "source": "analytic: the whole stack overturns about the base toe, alpha = b / H"}))
    add(B.portal(dim=2, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, mu=0.8, name="portal-2d",
                 expected={"alpha": 0.2, "rtol": 1e-6,
                           "source": "analytic: sway mechanism with the lintel translating, alpha = b / h of the columns"}))
    add(B.running_bond_wall(3, 3, dim=2, mu=0.65, name="wall-3x3-2d"))
    add(B.running_bond_wall(6, 5, dim=3, mu=0.65, name="wall-6x5-3d"))
    add(B.arch(9, R=1.0, t=0.15, dim=2, mu=0.6, name="arch-semicircular-9-2d"))
    add(B.arch(7, R=1.5, t=0.2, span_deg=120, dim=3, mu=0.6, name="arch-segmental-7-3d"))
    add(B.corner_walls(courses=4, len_a=4, len_b=3, name="corner-walls-3d"))
    return out


def write(check: bool = False) -> int:
    CATALOG_DIR.mkdir(exist_ok=True)
    wanted = {f"{name}.json": json.dumps(d, indent=1) + "\n" for name, d in entries().items()}
    stale = []
    for fname, text in wanted.items():
        p = CATALOG_DIR / fname
        if check:
            if not p.exists() or p.read_text() != text:
                stale.append(fname)
        else:
            p.write_text(text)
    extra = sorted(p.name for p in CATALOG_DIR.glob("*.json") if p.name not in wanted)
    if check and (stale or extra):
        print(f"catalog out of date: {', '.join(stale + extra)} (run: python -m scenes.catalog)", file=sys.stderr)
        return 1
    if not check:
        for name in extra:
            (CATALOG_DIR / name).unlink()
        print(f"wrote {len(wanted)} scenes to {CATALOG_DIR}")
    return 0


def catalog_files() -> list[Path]:
    return sorted(CATALOG_DIR.glob("*.json"), key=lambda p: list(entries()).index(p.stem)
                  if p.stem in entries() else 10**6)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m scenes.catalog", description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="only check that the JSON files match the builders")
    return write(check=ap.parse_args(argv).check)


if __name__ == "__main__":
    sys.exit(main())
