"""The catalog: JSON files in step with their builders, and every reference value met."""
import json

import numpy as np
import pytest

from limit.analysis import analyse
from limit.model.scene import load_scene
from tests.conftest import catalog_params
from scenes.catalog import FOUR_HINGE, catalog_files, entries, stored_references, write

FILES = catalog_files()
WITH_REF = [p for p in FILES if json.loads(p.read_text()).get("expected")]


def test_catalog_json_matches_builders():
    """Every file is its builder's output (``python -m scenes.catalog --check``), the four-hinge
    references taken as the files store them: the next test checks those against the searches."""
    assert write(check=True, references=stored_references()) == 0


# the 27-voussoir arch's search takes about 50 s, the 9-voussoir arch's and the arch on piers' 3-4 s
@pytest.mark.parametrize("name", [n if n == "arch-segmental-7-3d" else pytest.param(n, marks=pytest.mark.slow)
                                  for n in FOUR_HINGE])
def test_stored_four_hinge_references_are_the_searches(name):
    """The four-hinge alpha each file stores is its search's, rounded to 1e-10, as the builder
    writes it."""
    others = {k: v for k, v in stored_references().items() if k != name}
    assert entries(others)[name]["expected"]["alpha"] == stored_references()[name]


def test_every_scene_loads():
    for p in FILES:
        load_scene(p)


def test_no_catalog_scene_tunes_or_skips_a_dem_engine_of_its_own():
    """The DEM stages run every catalog scene with the knobs' rules (dem_validation/params.py,
    engines/yade/refine.py, the LMGC90 time-step check), as they run a user's scene: no scene
    carries knobs of its own, and none opts out of an engine (a scene an engine cannot model is
    skipped by the engine itself, with the reason). ``meta.dem`` and ``meta.lmgc`` hold only the
    measured costs that order the stages."""
    own = {p.stem: {stage: sorted(set(spec) - {"cost_s"})}
           for p in FILES for stage, spec in (json.loads(p.read_text()).get("meta") or {}).items()
           if stage in ("dem", "lmgc") and set(spec) - {"cost_s"}}
    assert own == {}


@pytest.mark.parametrize("path", catalog_params(WITH_REF))  # a catalog sweep: FAST_CATALOG in the fast subset
def test_reference_values(path):
    d = json.loads(path.read_text())
    exp = d["expected"]
    res = analyse(load_scene(d), method="auto").data
    rtol = exp.get("rtol", 1e-6)
    if exp.get("alpha_lp") is not None:
        assert res["lp"]["alpha"] == pytest.approx(exp["alpha_lp"], rel=rtol)
    if exp.get("alpha") is not None:
        assert res["nlp"]["status"] in ("optimal", "skipped")
        assert res["nlp"]["alpha"] == pytest.approx(exp["alpha"], rel=rtol)


def _polygon(block):
    """The block's outline (counter-clockwise vertices, m), read from the scene file's box or vertices."""
    if "box" in block:
        (cx, cy), (w, h) = block["box"]["center"], block["box"]["size"]
        return np.array([[cx - w / 2, cy - h / 2], [cx + w / 2, cy - h / 2],
                         [cx + w / 2, cy + h / 2], [cx - w / 2, cy + h / 2]])
    return np.asarray(block["vertices"], float)


def _shoelace(P):
    """Area (m2) and centroid (m) of a simple polygon by the shoelace formula."""
    x, y = P[:, 0], P[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    A = cross.sum() / 2
    return A, np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * A)


def test_wall_3x3_opening_alpha_by_virtual_work():
    """wall-3x3-opening-2d, alpha = 5/14 by hand. c1-3 ([1.0, 1.2] x [0.4, 0.8] m, area 0.08 m2,
    centroid (1.1, 0.6)) and c2-2 ([0.8, 1.2] x [0.8, 1.2], 0.16 m2, centroid (1.0, 1.0)) turn
    together clockwise about the toe o = (1.2, 0.4), the top right corner of c0-2. A unit rotation
    moves a point p by v = (p_y - o_y, o_x - p_x) m: centroids (0.2, 0.1) and (0.6, 0.2). With the
    weight rho g t A (N) of each block: work against the dead load rho g t (0.08 * 0.1 + 0.16 * 0.2)
    = 0.04 rho g t; work of the live load (1 g along +x) rho g t (0.08 * 0.2 + 0.16 * 0.6) = 0.112
    rho g t; alpha = 0.04 / 0.112 = 5/14. Every point of the pair moves up and towards +x (x <= 1.2,
    y >= 0.4) and no other block lies there, so the joints with c0-2, c1-2 and c2-1 only open
    (no dissipation, whatever mu). Computed here from the file's polygons (numpy shoelace)."""
    d = json.loads(next(p for p in FILES if p.stem == "wall-3x3-opening-2d").read_text())
    assert d["expected"]["alpha"] == pytest.approx(5 / 14, rel=1e-12)
    assert d["loads"]["dead"] == [{"type": "self_weight"}]
    assert d["loads"]["live"] == [{"type": "body_force", "direction": [1.0, 0.0]}]
    g_live = np.array(d["loads"]["live"][0]["direction"], float)  # per unit weight
    o = np.array([1.2, 0.4])
    blocks = {b["id"]: _polygon(b) for b in d["blocks"]}
    moving = ("c1-3", "c2-2")

    def v(p):
        r = np.asarray(p) - o
        return np.stack([r[..., 1], -r[..., 0]], axis=-1)

    work_dead = work_live = 0.0
    for bid in moving:
        A, c = _shoelace(blocks[bid])
        assert A > 0
        work_dead += A * v(c)[1]          # lifting the weight A (x rho g t)
        work_live += A * g_live @ v(c)
        assert np.all(v(blocks[bid]) >= -1e-12)  # every vertex moves up and towards +x: joints open
    assert work_dead == pytest.approx(0.04, rel=1e-9)
    assert work_live == pytest.approx(0.112, rel=1e-9)
    assert work_dead / work_live == pytest.approx(5 / 14, rel=1e-9)
    # the pair moves up and towards +x only: no block at rest may lie to its right or above it
    for bid, P in blocks.items():
        if bid not in moving:
            assert not (P[:, 0].min() >= 1.2 - 1e-9 and P[:, 1].max() > 0.4 + 1e-9), bid
            assert P[:, 1].min() < 1.2 - 1e-9, bid
