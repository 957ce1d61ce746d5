"""The scene catalog: every entry built by :mod:`scenes.builders` and kept as JSON
in ``scenes/catalog/``. ``python -m scenes.catalog`` rewrites the files;
``python -m scenes.catalog --check`` fails if a file differs from its builder.
"""
from __future__ import annotations

import argparse
import json
import math
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
    add(B.stack(3, dim=3, b=0.3, h=0.4, t=0.3, mu=0.8, name="stack-3-3d",
                expected={"alpha": 0.3 / 1.2, "rtol": 1e-6,
                          "source": "analytic: the whole stack overturns about the base edge, alpha = b / H"}))
    add(B.portal(dim=3, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, mu=0.8, name="portal-3d",
                 expected={"alpha": 0.2, "rtol": 1e-6,
                           "source": "analytic: sway mechanism with the lintel translating, alpha = b / h of the columns"}))
    oop = B.running_bond_wall(6, 4, dim=3, L=0.4, H=0.175, T=0.2, mu=0.8, name="wall-out-of-plane-3d",
                              expected={"alpha": 0.2 / 1.05, "rtol": 1e-6,
                                        "source": "analytic: the wall overturns about its base edge, alpha = t / H"})
    oop["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]
    add(oop)
    th = math.radians(30.0)
    obl = B.single_block(dim=3, b=0.4, h=1.0, t=0.25, mu=2.0, name="block-oblique-3d",
                         expected={"alpha": _oblique(0.2, 0.125, 1.0, th), "rtol": 1e-6,
                                   "source": "analytic: least b_e / ((h/2) d.n_e) over the base edges, load at 30 deg"})
    obl["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    add(obl)
    add(B.side_by_side(dim=2, mu=0.5, name="side-by-side-2d",
                       expected={"alpha": B.side_by_side_alpha(mu=0.5), "alpha_lp": 7 / 17, "rtol": 1e-6,
                                 "source": "analytic (scenes/builders.side_by_side): frictional 23/61, associative 7/17"},
                       meta={"title": "A slender block pushing a squat one",
                             "notes": "Rocking and sliding combine: the associative LP must dilate where the squat "
                                      "block slides and overestimates alpha by 9 %."}))
    add(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2, name="wall-3x3-opening-2d",
                            expected={"alpha": 5 / 14, "alpha_lp": 1.0, "rtol": 1e-4,
                                      "source": "global minimum by mixed-integer LP (limit/milp.py, proven); "
                                                "the issue's DEM probe found 0.357"},
                            meta={"title": "3 x 3 running-bond wall whose joints open while they slide",
                                  "notes": "The LP's dilatant mechanism needs alpha = 1.0; without dilatancy the end "
                                           "blocks rock about a toe while the joints above open and slide at zero "
                                           "normal force, at 5/14."}))
    add(B.running_bond_wall(6, 5, dim=3, mu=0.65, name="wall-6x5-3d"))
    add(B.arch(9, R=1.0, t=0.15, dim=2, mu=0.6, name="arch-semicircular-9-2d"))
    add(B.arch(7, R=1.5, t=0.2, span_deg=120, dim=3, mu=0.6, name="arch-segmental-7-3d"))
    add(B.corner_walls(courses=4, len_a=4, len_b=3, name="corner-walls-3d"))
    return out


def _oblique(half_x, half_y, h, theta):
    """Least b_e / ((h / 2) d . n_e) over the base edges of a box under a load at angle theta."""
    d = (math.cos(theta), math.sin(theta))
    cands = [dist / (h / 2 * dn) for dn, dist in ((d[0], half_x), (-d[0], half_x), (d[1], half_y), (-d[1], half_y))
             if dn > 1e-12]
    return min(cands)


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
