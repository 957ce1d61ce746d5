"""The catalog: JSON files in step with their builders, and every reference value met."""
import json

import pytest

from limit.analysis import analyse
from limit.scene import load_scene
from scenes.catalog import catalog_files, main as catalog_main

FILES = catalog_files()
WITH_REF = [p for p in FILES if json.loads(p.read_text()).get("expected")]


def test_catalog_json_matches_builders():
    assert catalog_main(["--check"]) == 0


def test_every_scene_loads():
    for p in FILES:
        load_scene(p)


@pytest.mark.parametrize("path", WITH_REF, ids=[p.stem for p in WITH_REF])
def test_reference_values(path):
    d = json.loads(path.read_text())
    exp = d["expected"]
    res = analyse(load_scene(d), method="auto")
    rtol = exp.get("rtol", 1e-6)
    if exp.get("alpha_lp") is not None:
        assert res["lp"]["alpha"] == pytest.approx(exp["alpha_lp"], rel=rtol)
    if exp.get("alpha") is not None:
        assert res["nlp"]["status"] in ("optimal", "skipped")
        assert res["nlp"]["alpha"] == pytest.approx(exp["alpha"], rel=rtol)
