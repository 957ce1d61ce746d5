"""Mutation fuzz of the catalog's small scenes: every mutant is either rejected with a
SceneError (exit 2 at the command line) or analysed to a status, never an internal error.

Mutations (seeded, reproducible): a value swapped for an odd one (null, a string, an empty
list or object, a boolean, 0, -1, 1e308, 1e-12), a key deleted, a number scaled (x0, x-1,
x1e-9, x1e9). Mutants are analysed by the LP (step 1), the part that sees every input.

Load mutations (:func:`_mutate_loads`): a load's direction or force zeroed, turned, scaled
or with one component changed; the blocks it selects swapped for a fixed block, a free
one, "all" or a tag; a point force moved to another block or point; the live loads
dropped. These mutants run the whole analysis (``method="auto"``): where the LP finds no
mechanism, step 2 still runs, which is where a live load doing no work once ended in a
ZeroDivisionError.
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


def _vector_key(ld):
    return {"body_force": "direction", "point_force": "force"}.get(ld.get("type"))


def _mutate_loads(data, rng):
    """One seeded mutation of a scene's loads (see the module docstring)."""
    d = copy.deepcopy(data)
    loads = d.setdefault("loads", {})
    case = "live" if rng.random() < 0.8 or not loads.get("dead") else "dead"
    items = loads.setdefault(case, [])
    if not items or rng.random() < 0.05:
        loads[case] = []
        return d
    ld = rng.choice(items)
    blocks = d["blocks"]
    dim = d["dim"]
    kind = rng.choice(["vector", "magnitude", "select", "select", "point"])
    vk = _vector_key(ld)
    if kind in ("vector", "magnitude") and vk:
        vec = [float(x) for x in ld[vk]]
        if kind == "magnitude":
            k = rng.choice([0.0, -1.0, 1e-6, 10.0])
            ld[vk] = [x * k for x in vec]
        else:
            j = rng.randrange(dim)
            vec[j] = rng.choice([0.0, -vec[j], 2.0 * vec[j] + 1.0, 0.0])
            if rng.random() < 0.3:
                vec = [rng.choice([0.0, 0.0, 1.0, -1.0]) for _ in range(dim)]
            ld[vk] = vec
    elif ld.get("type") == "point_force":
        b = rng.choice(blocks)
        if kind == "point" and "box" in b:
            c, size = b["box"]["center"], b["box"]["size"]
            ld["point"] = [ci + rng.choice([0.0, 0.25, -0.5, 0.9, 3.0]) * si for ci, si in zip(c, size)]
        else:
            ld["block"] = b["id"]
            ld.pop("point", None)
    else:
        fixed = [b["id"] for b in blocks if b.get("fixed")]
        tags = sorted({t for b in blocks for t in b.get("tags", [])})
        choice = rng.choice(["fixed", "one", "all", "tags"])
        if choice == "fixed" and fixed:
            ld["blocks"] = [rng.choice(fixed)]
        elif choice == "one":
            ld["blocks"] = [rng.choice(blocks)["id"]]
        elif choice == "tags" and tags:
            ld["blocks"] = {"tags": [rng.choice(tags)]}
        else:
            ld["blocks"] = "all"
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
                res = analyse(load_scene(mutant), method="lp").data
            except SceneError:
                counts["rejected"] += 1
                continue
            except Exception as exc:  # noqa: BLE001 - the failure this test exists to catch
                pytest.fail(f"mutant {k}: internal error {type(exc).__name__}: {exc}\n{json.dumps(mutant)[:2000]}")
        assert res["lp"]["status"] in STATUSES, (k, res["lp"])
        counts["analysed"] += 1
    assert counts["rejected"] > 100 and counts["analysed"] > 100, counts  # both paths exercised


LOAD_SEED, LOAD_MUTANTS = 20261127, 120


@pytest.mark.slow  # about 30 s: the whole analysis of every mutant that loads
def test_load_mutants_are_rejected_or_analysed():
    """Mutated loads are rejected naming the load, or analysed, steps 1 and 2, to a status;
    among them live loads that do no work on any free block (rejected, naming the load)."""
    rng = random.Random(LOAD_SEED)
    scenes = [json.loads(p.read_text()) for p in SMALL]
    counts = {"rejected": 0, "analysed": 0, "no_work": 0}
    for k in range(LOAD_MUTANTS):
        mutant = _mutate_loads(rng.choice(scenes), rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SceneWarning)
            try:
                res = analyse(load_scene(mutant), method="auto").data
            except SceneError as exc:
                counts["rejected"] += 1
                counts["no_work"] += "does no work" in str(exc) or "no live load" in str(exc)
                continue
            except Exception as exc:  # noqa: BLE001 - the failure this test exists to catch
                pytest.fail(f"mutant {k}: internal error {type(exc).__name__}: {exc}\n"
                            f"{json.dumps(mutant['loads'])}")
        assert res["lp"]["status"] in STATUSES, (k, res["lp"])
        counts["analysed"] += 1
    assert counts["no_work"] >= 3 and counts["analysed"] > 30, counts


DEMAND_SEED, DEMAND_MUTANTS = 20261128, 100
DEMAND_KEYS = ["ag_g", "S", "F0", "TB", "TC", "TD", "q", "eta", "Z", "H", "N", "T1", "xi1", "xi_mech", "fc",
               "Tc_star", "soil", "topography", "topography_ratio", "site_class"]
DEMAND_VALUES = ODD + [0.3, 2.5, 0.05, 1.5, 12, "A", "C", "F", "T2", "T9", [0.3]]


@pytest.mark.slow  # the LP and the code check of every mutant that loads
def test_demand_mutants_are_rejected_or_checked():
    """Mutated ``demand`` objects (on the catalog's block-rocking-2d, given {"ag_g": 0.2}): keys set to
    odd or plausible values (the site's keys among them, and a key no demand has), deleted, or
    the site's keys added together. Each mutant is rejected naming a key, or analysed with a
    verdict, never an internal error."""
    rng = random.Random(DEMAND_SEED)
    base = json.loads(next(p for p in SMALL if p.stem == "block-rocking-2d").read_text())
    base["demand"] = {"ag_g": 0.2}
    counts = {"rejected": 0, "checked": 0, "site": 0}
    for k in range(DEMAND_MUTANTS):
        m = copy.deepcopy(base)
        dem = m["demand"]
        for _ in range(rng.choice([1, 1, 2, 3])):
            key = rng.choice(DEMAND_KEYS)
            if rng.random() < 0.2:
                dem.pop(key, None)
            else:
                dem[key] = copy.deepcopy(rng.choice(DEMAND_VALUES))
        if rng.random() < 0.3:
            dem.update(F0=2.5, Tc_star=rng.choice([0.2, 0.35, 0.5]), soil=rng.choice("ABCDE"))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SceneWarning)
            try:
                res = analyse(load_scene(m), method="lp").data
            except SceneError as exc:
                assert "demand" in str(exc) or "ag_g" in str(exc), (k, str(exc))
                counts["rejected"] += 1
                continue
            except Exception as exc:  # noqa: BLE001 - the failure this test exists to catch
                pytest.fail(f"mutant {k}: internal error {type(exc).__name__}: {exc}\n{json.dumps(dem)}")
        assert res["verdict"]["status"] in ("done", "no mechanism", "failed"), (k, res["verdict"])
        counts["checked"] += 1
        counts["site"] += bool((res["verdict"].get("demand") or {}).get("site"))
    assert counts["rejected"] > 10 and counts["checked"] > 10 and counts["site"] > 3, counts


def _mutate_entries(entries: list, rng, keys, values, pick_copy) -> list:
    """One seeded mutation of a list of objects, in place: an entry doubled (``pick_copy`` chooses
    which) or dropped now and then, then one or two of its entries' keys set to one of ``values``
    or deleted. Returns the list."""
    if rng.random() < 0.2:
        entries.append(copy.deepcopy(pick_copy(entries)) if entries else {})
    if entries and rng.random() < 0.1:
        entries.pop(rng.randrange(len(entries)))
    for _ in range(rng.choice([1, 1, 2])):
        if not entries:
            break
        e = rng.choice(entries)
        key = rng.choice(keys)
        if rng.random() < 0.2:
            e.pop(key, None)
        else:
            e[key] = copy.deepcopy(rng.choice(values))
    return entries


def _analysed(m: dict, k: int, key: str, counts: dict) -> bool:
    """Mutant ``k`` (the scene ``m``) analysed, both steps, to a status (True), or rejected naming
    ``key`` (False, counted); an internal error fails the test, showing ``m[key]``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SceneWarning)
        try:
            res = analyse(load_scene(m), method="auto").data
        except SceneError as exc:
            assert key in str(exc), (k, str(exc))
            counts["rejected"] += 1
            return False
        except Exception as exc:  # noqa: BLE001 - the failure this test exists to catch
            pytest.fail(f"mutant {k}: internal error {type(exc).__name__}: {exc}\n{json.dumps(m[key])}")
    assert res["lp"]["status"] in STATUSES, (k, res["lp"])
    counts["analysed"] += 1
    return True


JOINTS_SEED, JOINTS_MUTANTS = 20261129, 60
JOINT_KEYS = ["mu", "cohesion", "tensile_strength", "fc", "between", "colour"]
JOINT_VALUES = ODD + [0.2, 0.6, 1.5, 500.0, 2e4, 3e5, {"blocks": ["s0", "s1"]}, {"tags": ["course-0", "course-1"]},
                      {"tags": ["course-0"]}, {"blocks": ["s0", "s0"]}, {"blocks": ["s0", "nope"]}, {"plane": [0, 1]},
                      {"plane": {"point": [0, 0.3], "normal": [0, 1]}}, {"plane": {"point": [0, 0.3], "normal": [0, 0]}},
                      {"plane": {"point": [0, 0.3], "normal": [1e308, -1e308]}}, {"plane": {"point": [0, "a"]}}]


@pytest.mark.slow  # steps 1 and 2 of every mutant that loads (3 blocks each)
def test_joint_group_mutants_are_rejected_or_analysed():
    """Mutated ``joints`` entries on a three-block stack (given one valid group with mu, cohesion
    and tension): keys set to odd or plausible values, deleted, entries added or dropped. Each
    mutant is rejected naming ``joints[k]``, or analysed (both steps) to a status, never an
    internal error; bonded mutants among them."""
    from scenes import builders as B

    rng = random.Random(JOINTS_SEED)
    base = B.stack(3, dim=2, b=0.5, h=0.3, mu=0.6)
    base["joints"] = [{"between": {"tags": ["course-0", "course-1"]}, "mu": 0.4, "cohesion": 2000.0,
                       "tensile_strength": 500.0}]
    counts = {"rejected": 0, "analysed": 0, "bonded": 0}
    for k in range(JOINTS_MUTANTS):
        m = copy.deepcopy(base)
        js = _mutate_entries(m["joints"], rng, JOINT_KEYS, JOINT_VALUES, lambda es: rng.choice(es))
        if _analysed(m, k, "joints", counts):
            counts["bonded"] += any((e.get("cohesion") or 0) > 0 or (e.get("tensile_strength") or 0) > 0
                                    for e in js if isinstance(e, dict))
    assert counts["rejected"] > 5 and counts["analysed"] > 10 and counts["bonded"] > 5, counts


TIES_SEED, TIES_MUTANTS = 20261130, 60
TIE_KEYS = ["id", "from", "to", "capacity", "prestress", "colour"]
TIE_VALUES = ODD + [500.0, 2000.0, "rod", {"block": "block", "point": [0.0, 1.0]},
                    {"block": "post", "point": [-0.3, 1.0]}, {"block": "block", "point": [0.0, 5.0]},
                    {"block": "base", "point": [0.0, -0.1]}, {"block": "nope", "point": [0.0, 1.0]},
                    {"block": "block"}, {"point": [0.0, 1.0]}, {"block": "block", "point": [0.0]}]


@pytest.mark.slow  # steps 1 and 2 of every mutant that loads (one block, a post and a tie)
def test_tie_mutants_are_rejected_or_analysed():
    """Mutated ``ties`` entries on the catalog's tied block: keys set to odd or plausible values,
    deleted, entries doubled or dropped. Each mutant is rejected naming ``ties[k]`` (or the schema's
    key), or analysed, both steps, to a status, never an internal error."""
    rng = random.Random(TIES_SEED)
    base = json.loads(next(p for p in catalog_files() if p.stem == "block-tied-2d").read_text())
    counts = {"rejected": 0, "analysed": 0}
    for k in range(TIES_MUTANTS):
        m = copy.deepcopy(base)
        _mutate_entries(m["ties"], rng, TIE_KEYS, TIE_VALUES, lambda es: es[0])
        _analysed(m, k, "ties", counts)
    assert counts["rejected"] > 10 and counts["analysed"] > 10, counts
