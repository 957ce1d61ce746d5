"""Every rejected input gives exit status 2 and one line naming the fault (no traceback)."""
import copy
import json

import pytest

from limit.cli import main
from limit.errors import SceneError
from limit.model.scene import load_scene
from scenes import builders as B
from tests.conftest import run_module

GOOD2 = B.running_bond_wall(2, 2, dim=2)
GOOD3 = B.running_bond_wall(2, 2, dim=3)


def edited(base, fn):
    d = copy.deepcopy(base)
    fn(d)
    return d


def check_rejected(capsys, path, *fragments):
    code = main(["info", str(path)])
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for frag in fragments:
        assert frag in lines[0], (frag, lines[0])
    return lines[0]


def test_good_scene_accepted(capsys, write_scene):
    assert main(["info", str(write_scene(GOOD2))]) == 0
    assert main(["info", str(write_scene(GOOD3))]) == 0


def test_missing_file(capsys, tmp_path):
    check_rejected(capsys, tmp_path / "nope.json", "no such file")


def test_directory_instead_of_file(capsys, tmp_path):
    check_rejected(capsys, tmp_path, "directory")


def test_binary_file(capsys, tmp_path):
    p = tmp_path / "bin.json"
    p.write_bytes(b"\xff\xfe\x00garbage")
    check_rejected(capsys, p, "UTF-8")


def test_not_json(capsys, write_scene):
    check_rejected(capsys, write_scene('{"format": "blockscene/1", "dim": 2, "blocks": ['), "not valid JSON", "line 1")


def test_top_level_not_object(capsys, write_scene):
    check_rejected(capsys, write_scene("[1, 2]"), "JSON object")


def test_wrong_format(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update(format="blockscene/2"))), "format", "blockscene/2")


def test_missing_format(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.pop("format"))), "format")


@pytest.mark.parametrize("dim", [1, 4, "3", None])
def test_wrong_dim(capsys, write_scene, dim):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update(dim=dim))), "dim")


@pytest.mark.parametrize("key,value,frag", [
    ("friction", "high", "friction: must be number"),
    ("density", [2000], "density: must be number"),
    ("blocks", {"a": 1}, "blocks: must be array"),
    ("name", 12, "name: must be string"),
])
def test_wrong_top_level_types(capsys, write_scene, key, value, frag):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update({key: value}))), frag)


def test_wrong_block_types(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["blocks"][1].update(fixed="yes"))),
                   "blocks[1] (block 'c0-0').fixed", "boolean")
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["blocks"][2]["box"].update(size=[0.4, "x"]))),
                   "blocks[2] (block 'c0-1').box.size[1]", "number")
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["blocks"][2].update(id=7))), "blocks[2].id", "string")


@pytest.mark.parametrize("text,frag", [("NaN", "NaN"), ("Infinity", "Infinity"), ("-Infinity", "-Infinity"),
                                       ("1e999", "1e999")])
def test_non_finite_numbers(capsys, write_scene, text, frag):
    s = json.dumps(GOOD2).replace('"friction": 0.65', f'"friction": {text}')
    check_rejected(capsys, write_scene(s), "friction", "non-finite", frag)
    s = json.dumps(GOOD2).replace('"center": [0.2, 0.0875]', f'"center": [0.2, {text}]')
    assert text in s
    check_rejected(capsys, write_scene(s), "blocks[1] (block 'c0-0').box.center[1]", "non-finite")


@pytest.mark.parametrize("edit,frag", [
    (lambda d: d["blocks"][1]["box"].update(center=[1e9, 0.0]), "blocks[1] (block 'c0-0').box.center[0]"),
    (lambda d: d.update(density=1e9), "density"),
    (lambda d: d.update(friction=1e7), "friction"),
    (lambda d: d.update(gravity=[0.0, -1e6]), "gravity[1]"),
    (lambda d: d["blocks"][1].update(density=0), "blocks[1] (block 'c0-0').density"),
])
def test_absurd_numbers(capsys, write_scene, edit, frag):
    check_rejected(capsys, write_scene(edited(GOOD2, edit)), frag, "out of range")


def test_zero_gravity(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update(gravity=[0, 0]))), "gravity", "zero")


def test_duplicate_ids(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["blocks"][2].update(id="c0-0"))),
                   "duplicate block id 'c0-0'")


@pytest.mark.parametrize("base,edit,frag", [
    (GOOD2, lambda d: d["blocks"][1]["box"].update(center=[0.2, 0.1, 0.0]), "box.center: has 3 coordinates, a 2D scene needs 2"),
    (GOOD3, lambda d: d["blocks"][1]["box"].update(size=[0.4, 0.2]), "box.size: has 2 coordinates, a 3D scene needs 3"),
    (GOOD3, lambda d: d.update(gravity=[0, -9.81]), "gravity: has 2 coordinates"),
    (GOOD2, lambda d: d["loads"]["live"][0].update(direction=[1, 0, 0]), "loads.live[0].direction: has 3"),
])
def test_wrong_dimension_coordinates(capsys, write_scene, base, edit, frag):
    check_rejected(capsys, write_scene(edited(base, edit)), frag)


def test_wrong_dimension_vertex(capsys, write_scene):
    d = edited(GOOD3, lambda d: None)
    d["blocks"].append({"id": "tet", "vertices": [[5, 5, 0], [6, 5, 0], [5, 6], [5, 5, 1]]})
    check_rejected(capsys, write_scene(d), "block 'tet'", "vertices[2]", "has 2 coordinates")


@pytest.mark.parametrize("edit,frag", [
    (lambda d: d["loads"]["live"][0].update(blocks=["c0-0", "ghost"]), "loads.live[0].blocks[1]: unknown block id 'ghost'"),
    (lambda d: d["loads"].update(dead=[{"type": "point_force", "block": "ghost", "force": [1, 0]}]), "loads.dead[0].block: unknown block id 'ghost'"),
    (lambda d: d.update(interfaces={"friction": [{"blocks": ["c0-0", "ghost"], "mu": 0.3}]}), "interfaces.friction[0].blocks[1]: unknown block id 'ghost'"),
    (lambda d: d["loads"]["live"][0].update(blocks={"tags": ["nothing"]}), "no block carries"),
])
def test_unknown_ids(capsys, write_scene, edit, frag):
    check_rejected(capsys, write_scene(edited(GOOD2, edit)), frag)


def test_unknown_load_type(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["loads"]["live"][0].update(type="wind"))),
                   "loads.live[0].type", "unknown value \"wind\"")


def test_load_missing_field(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d["loads"]["live"][0].pop("direction"))),
                   "loads.live[0]", "missing required key 'direction'")


@pytest.mark.parametrize("base,blk,frag", [
    (GOOD2, {"id": "z", "box": {"center": [5, 5], "size": [0, 1]}}, "box.size[0]"),
    (GOOD2, {"id": "z", "box": {"center": [5, 5], "size": [1, -1]}}, "box.size[1]"),
    (GOOD2, {"id": "z", "vertices": [[5, 5], [6, 6], [7, 7]]}, "collinear"),
    (GOOD2, {"id": "z", "vertices": [[5, 5], [5, 5], [5, 5]]}, "block 'z'"),
    (GOOD3, {"id": "z", "vertices": [[5, 5, 0], [6, 5, 0], [5, 6, 0], [6, 6, 0]]}, "coplanar"),
    (GOOD3, {"id": "z", "box": {"center": [5, 5, 5], "size": [1, 1, 0]}}, "box.size[2]"),
])
def test_degenerate_blocks(capsys, write_scene, base, blk, frag):
    d = copy.deepcopy(base)
    d["blocks"].append(blk)
    line = check_rejected(capsys, write_scene(d), frag)
    assert "'z'" in line


def test_non_convex_2d(capsys, write_scene):
    d = copy.deepcopy(GOOD2)
    d["blocks"].append({"id": "L", "vertices": [[5, 0], [7, 0], [7, 1], [6, 0.3], [5, 1]]})
    check_rejected(capsys, write_scene(d), "block 'L'", "not convex")


def test_non_convex_3d(capsys, write_scene):
    d = copy.deepcopy(GOOD3)
    cube = [[x, y, z] for x in (5, 6) for y in (5, 6) for z in (0, 1)]
    d["blocks"].append({"id": "dent", "vertices": cube + [[5.5, 5.5, 0.8]]})
    check_rejected(capsys, write_scene(d), "block 'dent'", "not convex")


def test_overlap_2d(capsys, write_scene):
    d = edited(GOOD2, lambda d: d["blocks"][2]["box"].update(center=[0.55, 0.0875]))
    check_rejected(capsys, write_scene(d), "overlap", "'c0-0'", "'c0-1'")


def test_overlap_3d(capsys, write_scene):
    d = edited(GOOD3, lambda d: d["blocks"][2]["box"].update(center=[0.59, 0.1, 0.0875]))
    check_rejected(capsys, write_scene(d), "overlap", "'c0-1'")


def _crossing_bars(dz):
    """Two square bars turned 45 degrees about their axes, crossing at right angles,
    the upper one lowered by dz onto the lower one's top edge: no face plane of
    either separates them, only the cross product of the two edges does."""
    h = 0.2 * 2 ** 0.5
    return [{"id": "x1", "box": {"center": [5, 5, 5], "size": [1, 0.2, 0.2],
                                 "rotation": {"axis": [1, 0, 0], "angle_deg": 45}}},
            {"id": "x2", "box": {"center": [5, 5, 5 + h - dz], "size": [0.2, 1, 0.2],
                                 "rotation": {"axis": [0, 1, 0], "angle_deg": 45}}}]


def test_overlap_3d_edge_crossing(capsys, write_scene):
    d = copy.deepcopy(GOOD3)
    d["blocks"] += _crossing_bars(0.02)
    check_rejected(capsys, write_scene(d), "overlap", "'x1'", "'x2'")


def test_edge_crossing_with_gap_accepted(capsys, write_scene):
    d = copy.deepcopy(GOOD3)
    d["blocks"] += _crossing_bars(-0.01)
    assert main(["info", str(write_scene(d))]) == 0


def test_touching_is_not_overlap(capsys, write_scene):
    d = copy.deepcopy(GOOD3)
    d["blocks"] += [{"id": "p", "box": {"center": [5, 5, 5], "size": [1, 1, 1]}},
                    {"id": "q", "box": {"center": [6, 5.3, 5], "size": [1, 1, 1]}}]
    assert main(["info", str(write_scene(d))]) == 0


def test_no_fixed_block(capsys, write_scene):
    d = edited(GOOD2, lambda d: d["blocks"][0].pop("fixed"))
    check_rejected(capsys, write_scene(d), "no fixed block")


@pytest.mark.parametrize("edit,frag", [
    (lambda d: d.update(friction=-0.1), "friction"),
    (lambda d: d.update(interfaces={"friction": [{"blocks": ["c0-0", "c0-1"], "mu": -1}]}), "interfaces.friction[0].mu"),
])
def test_negative_friction(capsys, write_scene, edit, frag):
    check_rejected(capsys, write_scene(edited(GOOD2, edit)), frag, "out of range", ">= 0")


def test_no_blocks(capsys, write_scene):
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update(blocks=[]))), "blocks", "at least 1")


def test_box_and_vertices_both(capsys, write_scene):
    d = edited(GOOD2, lambda d: d["blocks"][1].update(vertices=[[0, 0], [1, 0], [0, 1]]))
    check_rejected(capsys, write_scene(d), "block 'c0-0'", "exactly one of 'box', 'vertices' or 'parts'")


@pytest.mark.slow  # about 1.5-2.5 s: limit info in a subprocess (test_malformed keeps a subprocess sample fast)
def test_subprocess_no_traceback(write_scene):
    """The real command: exit 2, one stderr line, nothing on stdout, no JSON written."""
    p = write_scene(edited(GOOD2, lambda d: d.update(friction=-1)))
    out = p.with_suffix(".out.json")
    r = run_module("limit", "info", p, "--json", out)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    assert "friction" in r.stderr
    assert not out.exists()


def _rocking_with(**extra):
    import json
    from pathlib import Path

    d = json.loads(Path("scenes/catalog/block-rocking-2d.json").read_text())
    d.update(extra)
    return d


def test_a_typo_in_a_key_warns_naming_it_and_the_closest_known_key():
    from limit.errors import SceneWarning

    with pytest.warns(SceneWarning, match=r"frction: unknown key \(did you mean 'friction'\?\)"):
        load_scene(_rocking_with(frction=0.3))


def test_unknown_keys_deep_in_the_file_name_the_block():
    from limit.errors import SceneWarning

    d = _rocking_with()
    d["blocks"][1]["fixd"] = True
    d["loads"]["live"][0]["directon"] = [1.0, 0.0]
    with pytest.warns(SceneWarning) as rec:
        load_scene(d)
    msgs = sorted(str(w.message) for w in rec)
    assert msgs == ["blocks[1] (block 'block').fixd: unknown key (did you mean 'fixed'?)",
                    "loads.live[0].directon: unknown key (did you mean 'direction'?)"]


@pytest.mark.slow  # about 4 s: limit solve and limit info in subprocesses
def test_strict_makes_an_unknown_key_an_error_and_exit_2(tmp_path):
    import json
    import subprocess
    import sys

    with pytest.raises(SceneError, match="frction"):
        load_scene(_rocking_with(frction=0.3), strict=True)
    path = tmp_path / "typo.json"
    path.write_text(json.dumps(_rocking_with(frction=0.3)))
    p = subprocess.run([sys.executable, "-m", "limit", "solve", str(path), "--strict"], capture_output=True, text=True)
    assert p.returncode == 2 and "error: frction: unknown key (did you mean 'friction'?)" in p.stderr
    p = subprocess.run([sys.executable, "-m", "limit", "info", str(path)], capture_output=True, text=True)
    assert p.returncode == 0 and "warning: frction: unknown key" in p.stderr


def test_catalog_scenes_have_no_unknown_key():
    from scenes.catalog import catalog_files

    for f in catalog_files():
        load_scene(f, strict=True)  # raises on any unknown key


@pytest.mark.parametrize("edit,match", [
    (lambda d: d["blocks"][1].update(fixed=True), "every block is fixed"),
    (lambda d: d["blocks"][1]["box"]["center"].__setitem__(1, 1.0), "block 'block' touches no other block"),
    (lambda d: d["blocks"][1]["box"]["size"].__setitem__(0, 1e-9), r"blocks\[1\] \(block 'block'\): 1e-09 m thin"),
])
def test_scenes_that_once_ended_in_an_internal_error_are_rejected_naming_the_block(edit, match):
    """Found by the mutation fuzz (tests/test_fuzz.py): no free block, a free block touching
    nothing, a block thinner than the geometric tolerance."""
    from limit.analysis import analyse

    d = _rocking_with()
    edit(d)
    with pytest.raises(SceneError, match=match):
        analyse(load_scene(d), method="lp")
