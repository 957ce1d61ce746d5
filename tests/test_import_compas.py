"""``limit import`` of compas JSON (scenes/importers/compas_json.py), on files written at test time
in the layouts compas writes: a compas 2 ``BlockModel`` (elements with a ``geometry`` mesh, and
contact polygons that are not blocks) and a compas 1 list of meshes (``datatype``)."""
import json

import pytest

from limit.analysis import analyse
from limit.cli import main
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene

BOX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]


def box(x0, x1, y0, y1, z0, z1, name=None, version=2):
    """A compas Mesh dict of an axis-aligned box (quad faces wound outwards)."""
    pts = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    data = {"attributes": {"name": name or "Mesh"}, "default_vertex_attributes": {"x": 0.0, "y": 0.0, "z": 0.0},
            "vertex": {str(k): {"x": x, "y": y, "z": z} for k, (x, y, z) in enumerate(pts)},
            "face": {str(k): f for k, f in enumerate(BOX_FACES)}, "facedata": {}, "edgedata": {}}
    return {("dtype" if version == 2 else "datatype"): "compas.datastructures/Mesh", "data": data}


def block_model(meshes):
    """A compas_dem BlockModel: one element per mesh (named by a uuid-like key), and a contact."""
    elements = {f"00000000-0000-0000-0000-{k:012d}": {"dtype": "compas_dem.elements/Block",
                                                      "data": {"name": "Block", "geometry": m}}
                for k, m in enumerate(meshes)}
    contact = {"dtype": "compas_dem.interactions/FrictionContact",
               "data": {"polygon": box(0, 1, 0, 1, 0.5, 0.5)}}
    return {"dtype": "compas_dem.models/BlockModel",
            "data": {"elements": elements, "graph": {"edge": {"0": {"1": {"interactions": [contact]}}}}}}


def _import(tmp_path, doc, *args):
    f = tmp_path / "model.json"
    f.write_text(json.dumps(doc))
    out = tmp_path / "scene.json"
    rc = main(["import", str(f), "-o", str(out), *args])
    return rc, (json.loads(out.read_text()) if out.exists() else None)


def test_a_block_model_gives_its_blocks_and_not_its_contacts(tmp_path):
    """A 2 x 1 x 0.5 base and a 0.4 wide, 1 tall, 1 deep block on it (z from 0.5 to 1.5): two
    blocks (the contact polygon is skipped), one interface of 0.4 x 1 = 0.4 m^2, the base fixed.
    The top block rocks about its toe at alpha = b / h = 0.4 (sliding needs mu = 0.6 > 0.4)."""
    rc, scene = _import(tmp_path, block_model([box(-1, 1, 0, 1, 0, 0.5), box(0, 0.4, 0, 1, 0.5, 1.5)]))
    assert rc == 0
    sc = load_scene(scene)
    assert len(sc.blocks) == 2 and sorted(b.volume for b in sc.blocks) == pytest.approx([0.4, 1.0], rel=1e-9)
    inter = find_interfaces(sc)
    assert len(inter) == 1 and inter.area[0] == pytest.approx(0.4, rel=1e-9)
    assert sum(b.fixed for b in sc.blocks) == 1 and sc.blocks[0].fixed
    assert analyse(sc, method="lp").data["lp"]["alpha"] == pytest.approx(0.4, rel=1e-6)


def test_a_compas1_list_of_meshes_named_by_their_attribute(tmp_path):
    rc, scene = _import(tmp_path, [[box(0, 2, 0, 1, 0, 1, "plinth", version=1)],
                                   [box(0, 1, 0, 1, 1, 2, "stone", version=1)]], "--fixed", "plinth")
    assert rc == 0
    assert [b["id"] for b in scene["blocks"]] == ["plinth", "stone"]
    assert [b["id"] for b in scene["blocks"] if b.get("fixed")] == ["plinth"]


@pytest.mark.parametrize("doc,frag", [
    ({"dtype": "compas.geometry/Point", "data": [0, 0, 0]}, "no compas mesh in it"),
    ([box(0, 1, 0, 1, 0, 1, "bad") | {"data": {**box(0, 1, 0, 1, 0, 1)["data"], "attributes": {"name": "bad"},
                                                 "face": {"0": [0, 1, 99]}}}], "mesh 'bad', face 0"),
])
def test_a_compas_file_without_usable_meshes_is_rejected_naming_it(tmp_path, capsys, doc, frag):
    rc, _ = _import(tmp_path, doc)
    assert rc == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "model.json" in err and frag in err


def test_a_file_that_is_not_json(tmp_path, capsys):
    f = tmp_path / "model.json"
    f.write_bytes(b"\x89PNG not json")
    assert main(["import", str(f), "-o", str(tmp_path / "s.json")]) == 2
    assert "not a JSON file" in capsys.readouterr().err
