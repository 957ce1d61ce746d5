"""Mutation fuzz of the catalog's small scenes: every mutant is either rejected with a
SceneError (exit 2 at the command line) or analysed to a status, never an internal error.

Mutations (seeded, reproducible): a value swapped for an odd one (null, a string, an empty
list or object, a boolean, 0, -1, 1e308, 1e-12), a key deleted, a number scaled (x0, x-1,
x1e-9, x1e9). Mutants are analysed by the LP (step 1), the part that sees every input.
"""
import copy
import json
import random
import warnings

import pytest

from limit.analysis import analyse
from limit.errors import SceneError, SceneWarning
from limit.model.scene import load_scene
from scenes.catalog import catalog_files

SEED, MUTANTS = 20261126, 3000
ODD = [None, "x", [], {}, True, 0, -1, 1e308, 1e-12]
STATUSES = {"optimal", "infeasible", "unbounded", "failed", "inaccurate"}
SMALL = [p for p in catalog_files() if len(json.loads(p.read_text())["blocks"]) <= 4]


def _paths(node, path=()):
    """Every (container path, key) in a JSON tree, 'meta' excepted."""
    if isinstance(node, dict):
        for k, v in node.items():
            if k == "meta" and not path:
                continue
            yield path, k
            yield from _paths(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield path, i
            yield from _paths(v, path + (i,))


def _mutate(data, rng):
    d = copy.deepcopy(data)
    path, key = rng.choice(list(_paths(d)))
    parent = d
    for p in path:
        parent = parent[p]
    kind = rng.choice(["odd", "delete", "scale"])
    val = parent[key]
    if kind == "delete" and isinstance(parent, dict):
        del parent[key]
    elif kind == "scale" and isinstance(val, (int, float)) and not isinstance(val, bool):
        parent[key] = val * rng.choice([0.0, -1.0, 1e-9, 1e9])
    else:
        parent[key] = copy.deepcopy(rng.choice(ODD))
    return d


@pytest.mark.slow  # about 9 s: analyses every mutant that loads
def test_catalog_mutants_are_rejected_or_analysed():
    rng = random.Random(SEED)
    scenes = [json.loads(p.read_text()) for p in SMALL]
    counts = {"rejected": 0, "analysed": 0}
    for k in range(MUTANTS):
        mutant = _mutate(rng.choice(scenes), rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SceneWarning)
            try:
                res = analyse(load_scene(mutant), method="lp")
            except SceneError:
                counts["rejected"] += 1
                continue
            except Exception as exc:  # noqa: BLE001 - the failure this test exists to catch
                pytest.fail(f"mutant {k}: internal error {type(exc).__name__}: {exc}\n{json.dumps(mutant)[:2000]}")
        assert res["lp"]["status"] in STATUSES, (k, res["lp"])
        counts["analysed"] += 1
    assert counts["rejected"] > 100 and counts["analysed"] > 100, counts  # both paths exercised
