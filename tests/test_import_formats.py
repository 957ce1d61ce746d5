"""``limit import``: each reader (OBJ, STL, PLY, DXF 2D and 3D) on boxes written at test time,
units, supports and the default loads (contract section 4; docs/importing.md)."""
import json

import numpy as np
import pytest

from limit.cli import main
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene

import trimesh  # noqa: E402  (pinned: a missing reader is a failure, not a skip)
import ezdxf  # noqa: E402


def _import(tmp_path, *args):
    out = tmp_path / "scene.json"
    rc = main(["import", *map(str, args), "-o", str(out)])
    return rc, (json.loads(out.read_text()) if out.exists() else None)


def _stack_meshes():
    """A 2 x 1 x 0.5 base box (z in [0, 0.5]) and a 1 x 1 x 1 box on it (z in [0.5, 1.5])."""
    base = trimesh.creation.box(extents=[2, 1, 0.5])
    base.apply_translation([0, 0, 0.25])
    top = trimesh.creation.box(extents=[1, 1, 1])
    top.apply_translation([0, 0, 1.0])
    return base, top


def _write_obj(path, meshes, names):
    """OBJ with one 'o' object per mesh, triangles as trimesh writes them."""
    lines, off = [], 0
    for m, name in zip(meshes, names):
        lines.append(f"o {name}")
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in m.vertices]
        lines += ["f " + " ".join(str(off + i + 1) for i in f) for f in m.faces]
        off += len(m.vertices)
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("fmt", ["obj", "stl", "ply"])
def test_two_boxes_volume_mass_interface(tmp_path, fmt):
    """Two boxes: volumes 2*1*0.5 = 1 and 1 m^3, mass (1 + 1) * 2000 = 4000 kg; one interface, the
    1 x 1 top face of the base (area 1 m^2); the lowest block (base) fixed by default."""
    base, top = _stack_meshes()
    if fmt == "obj":
        f = tmp_path / "stack.obj"
        _write_obj(f, [base, top], ["base", "top"])
        files = [f]
    else:  # one file per block
        files = []
        for m, name in ((base, "base"), (top, "top")):
            f = tmp_path / f"{name}.{fmt}"
            m.export(f)
            files.append(f)
    rc, scene = _import(tmp_path, *files)
    assert rc == 0
    sc = load_scene(scene)
    vols = sorted(b.volume for b in sc.blocks)
    assert vols == pytest.approx([1.0, 1.0], rel=1e-9)
    assert sc.total_mass == pytest.approx(4000.0, rel=1e-9)
    inter = find_interfaces(sc)
    assert len(inter) == 1 and inter.area[0] == pytest.approx(1.0, rel=1e-9)
    assert [b.id for b in sc.blocks if b.fixed] == ["base"]
    assert scene["loads"] == {"dead": [{"type": "self_weight"}],
                              "live": [{"type": "body_force", "direction": [1, 0, 0]}]}


def test_one_stl_split_into_parts_and_units_mm(tmp_path):
    """One STL holding both boxes, in mm (base 2000 x 1000 x 500 mm): two blocks by connectivity,
    lengths scaled by 1e-3, volumes 1 m^3 each."""
    base, top = _stack_meshes()
    both = trimesh.util.concatenate([base, top])
    both.apply_scale(1000.0)
    f = tmp_path / "both.stl"
    both.export(f)
    rc, scene = _import(tmp_path, f, "--units", "mm")
    assert rc == 0
    sc = load_scene(scene)
    assert sc.n_blocks == 2
    assert sorted(b.volume for b in sc.blocks) == pytest.approx([1.0, 1.0], rel=1e-9)
    assert np.ptp(sc.bbox(), axis=0) == pytest.approx([2.0, 1.0, 1.5], rel=1e-9)
    assert scene["meta"]["import"]["units"] == "mm"


def test_fixed_below_and_fixed_ids(tmp_path):
    """--fixed-below 0.6 (lowest points: base 0, top 0.5) fixes both boxes; --fixed top fixes only 'top'."""
    base, top = _stack_meshes()
    f = tmp_path / "stack.obj"
    _write_obj(f, [base, top], ["base", "top"])
    rc, scene = _import(tmp_path, f, "--fixed-below", "0.6", "--no-check")
    assert rc == 0
    assert sorted(b["id"] for b in scene["blocks"] if b.get("fixed")) == ["base", "top"]
    rc, scene = _import(tmp_path, f, "--fixed", "top", "--no-check")
    assert [b["id"] for b in scene["blocks"] if b.get("fixed")] == ["top"]
    rc, _ = _import(tmp_path, f, "--fixed", "nope")
    assert rc == 2


def test_dxf_2d_outlines(tmp_path):
    """A DXF with a 1000 x 200 mm base slab and a 300 x 600 mm pier on it ($INSUNITS 4, mm): a 2D
    scene, areas 0.2 and 0.18 m^2, thickness 1 m, mass (0.2 + 0.18) * 2000 = 760 kg, one interface of
    length 0.3 m; the layer 'piers' becomes the pier's tag."""
    doc = ezdxf.new()
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (1000, 0), (1000, 200), (0, 200)], close=True)
    msp.add_lwpolyline([(100, 200), (400, 200), (400, 800), (100, 800)], close=True, dxfattribs={"layer": "piers"})
    f = tmp_path / "pier.dxf"
    doc.saveas(f)
    rc, scene = _import(tmp_path, f)
    assert rc == 0
    assert scene["dim"] == 2
    sc = load_scene(scene)
    assert sorted(b.volume for b in sc.blocks) == pytest.approx([0.18, 0.2], rel=1e-9)
    assert sc.total_mass == pytest.approx(760.0, rel=1e-9)
    inter = find_interfaces(sc)
    assert len(inter) == 1 and inter.area[0] == pytest.approx(0.3, rel=1e-9)
    assert [b.get("tags") for b in scene["blocks"] if not b.get("fixed")] == [["piers"]]
    assert scene["loads"]["live"] == [{"type": "body_force", "direction": [1, 0]}]


def test_dxf_3dfaces_grouped_into_blocks(tmp_path):
    """Two unit cubes drawn as 3DFACEs (6 each), the second on the first: two blocks of 1 m^3 by
    shared corners, one interface of area 1 m^2."""
    doc = ezdxf.new()
    msp = doc.modelspace()
    for z0 in (0.0, 1.0):
        m = trimesh.creation.box(extents=[1, 1, 1])
        m.apply_translation([0.5, 0.5, z0 + 0.5])
        for face in m.faces:
            p = [tuple(m.vertices[i]) for i in face]
            msp.add_3dface(p + [p[-1]])
    f = tmp_path / "cubes.dxf"
    doc.saveas(f)
    rc, scene = _import(tmp_path, f)
    assert rc == 0
    sc = load_scene(scene)
    assert sorted(b.volume for b in sc.blocks) == pytest.approx([1.0, 1.0], rel=1e-9)
    assert len(find_interfaces(sc)) == 1


def test_dxf_2d_concave_outline_is_compound_and_open_polyline_closed(tmp_path):
    """An L outline (a 2 x 0.5 foot and a 0.5 x 1.5 upright: area 1 + 0.75 = 1.75 m^2) drawn as an
    LWPOLYLINE not marked closed, on a 3 x 0.2 slab: a compound block of convex parts whose areas
    sum to 1.75 m^2, and a warning that the outline was closed."""
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([(-0.5, -0.2), (2.5, -0.2), (2.5, 0), (-0.5, 0)], close=True)
    msp.add_lwpolyline([(0, 0), (2, 0), (2, 0.5), (0.5, 0.5), (0.5, 2), (0, 2)])
    f = tmp_path / "l.dxf"
    doc.saveas(f)
    rc, scene = _import(tmp_path, f, "--units", "m")
    assert rc == 0
    L = [b for b in scene["blocks"] if not b.get("fixed")][0]
    assert len(L["parts"]) >= 2
    from scipy.spatial import ConvexHull
    assert sum(ConvexHull(np.array(p["vertices"])).volume for p in L["parts"]) == pytest.approx(1.75, rel=1e-9)
    assert any("closed from their last point" in w for w in scene["meta"]["import"]["warnings"])
    sc = load_scene(scene)
    assert len(find_interfaces(sc)) >= 1


def test_one_stl_of_stacked_cubes_sharing_corners(tmp_path):
    """Three unit cubes stacked in one STL, sharing their joint corners and edges: three blocks of
    1 m^3 (the joints' coincident faces close the blocks on either side), two interfaces of 1 m^2."""
    cubes = []
    for z in (0.5, 1.5, 2.5):
        m = trimesh.creation.box(extents=[1, 1, 1])
        m.apply_translation([0, 0, z])
        cubes.append(m)
    f = tmp_path / "stack.stl"
    trimesh.util.concatenate(cubes).export(f)
    rc, scene = _import(tmp_path, f)
    assert rc == 0
    sc = load_scene(scene)
    assert sorted(b.volume for b in sc.blocks) == pytest.approx([1.0, 1.0, 1.0], rel=1e-9)
    inter = find_interfaces(sc)
    assert len(inter) == 2 and inter.area == pytest.approx([1.0, 1.0], rel=1e-9)


def test_import_progress_on_stderr_when_asked(tmp_path, capsys, monkeypatch):
    """LIMIT_LOG_LEVEL=INFO: one line per stage of a 3D import on stderr (the two boxes: 2 solids
    repaired, 12 planar faces, one facing pair, the written file checked), before the summary."""
    base, top = _stack_meshes()
    f = tmp_path / "stack.obj"
    _write_obj(f, [base, top], ["base", "top"])
    monkeypatch.setenv("LIMIT_LOG_LEVEL", "INFO")
    rc, _ = _import(tmp_path, f)
    err = capsys.readouterr().err
    assert rc == 0
    assert "import: 2 solids repaired" in err and "import: 12 faces" in err
    assert "import: 1 pairs of facing faces" in err and "checking it" in err
