"""``limit import`` on messy geometry: gaps closed, warped shared faces, concave blocks as compound
blocks, repeated faces, and rejected blocks (issue 42 item 2; docs/importing.md)."""
import json

import numpy as np
import pytest

from limit.cli import main
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene

import trimesh  # noqa: E402,F401  (pinned: a missing reader is a failure, not a skip)

# a hexahedron's corners in OBJ order and its six quads, outward
_HEX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def _box(x0, x1, y0, y1, z0, z1):
    return np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                     [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], dtype=float)


def _obj(path, blocks):
    """OBJ of polygon blocks: ``blocks`` a list of (name, corners (n, 3), faces)."""
    lines, off = [], 0
    for name, V, faces in blocks:
        lines.append(f"o {name}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in V.tolist()]
        lines += ["f " + " ".join(str(off + i + 1) for i in f) for f in faces]
        off += len(V)
    path.write_text("\n".join(lines) + "\n")
    return path


def _import(tmp_path, *args):
    out = tmp_path / "scene.json"
    rc = main(["import", *map(str, args), "-o", str(out)])
    return rc, (json.loads(out.read_text()) if out.exists() else None)


def test_gap_closed_to_one_interface(tmp_path):
    """A 1 x 1 x 0.5 base (z 0..0.5) and a 1 x 1 x 1 block 2 mm above it (z 0.502..1.502): the joint
    is snapped to the mid-plane z = 0.501, one interface of area 1 m^2; the volumes become
    0.501 and 1.001 m^3 (each block takes half the gap); the summary records the 2 mm gap."""
    f = _obj(tmp_path / "gap.obj", [("base", _box(0, 1, 0, 1, 0, 0.5), _HEX_FACES),
                                   ("top", _box(0, 1, 0, 1, 0.502, 1.502), _HEX_FACES)])
    rc, scene = _import(tmp_path, f)
    assert rc == 0
    sc = load_scene(scene)
    inter = find_interfaces(sc)
    assert len(inter) == 1 and inter.area[0] == pytest.approx(1.0, rel=1e-9)
    assert inter.centroid[0][2] == pytest.approx(0.501, abs=1e-12)
    assert sorted(b.volume for b in sc.blocks) == pytest.approx([0.501, 1.001], rel=1e-9)
    assert scene["meta"]["import"]["largest_gap_closed_m"] == pytest.approx(0.002, rel=1e-9)


def test_gap_zero_keeps_it_open(tmp_path):
    """--gap 0: the 2 mm gap stays; the loaded scene has no interface between the two blocks."""
    f = _obj(tmp_path / "gap.obj", [("base", _box(0, 1, 0, 1, 0, 0.5), _HEX_FACES),
                                   ("top", _box(0, 1, 0, 1, 0.502, 1.502), _HEX_FACES)])
    rc, scene = _import(tmp_path, f, "--gap", "0", "--no-check")
    assert rc == 0
    assert len(find_interfaces(load_scene(scene))) == 0


def test_warped_shared_face_gives_an_interface(tmp_path):
    """Two blocks sharing a warped quad (its corner (1, 1, 1) raised by 5 mm on a 1 x 1 face): both
    get the quad's least-squares plane, so the faces are exactly coplanar and the contact is found
    (one interface); the quad's corners are h/4 = 1.25 mm from that plane along z (the fitted plane
    of four corners with one raised by h passes h/4 from each), so no corner moves more than that
    and 1 % (its tilt)."""
    lower = _box(0, 1, 0, 1, 0, 1)
    upper = _box(0, 1, 0, 1, 1, 2)
    lower[6, 2] += 0.005  # the shared corner (1, 1, 1): top of the lower block
    upper[2, 2] += 0.005  # the same corner, bottom of the upper block
    f = _obj(tmp_path / "warp.obj", [("lower", lower, _HEX_FACES), ("upper", upper, _HEX_FACES)])
    rc, scene = _import(tmp_path, f, "--fixed", "lower")
    assert rc == 0
    sc = load_scene(scene)
    assert len(find_interfaces(sc)) == 1
    assert scene["meta"]["import"]["largest_corner_move_m"] <= 0.00125 * 1.01


def test_l_block_becomes_compound(tmp_path):
    """An L-shaped block (a 2 x 1 foot, 0.5 high, and a 0.5 x 1 x 1.5 upright on its left end:
    volume 2*1*0.5 + 0.5*1*1.5 = 1.75 m^3, hull larger) on a fixed 3 x 2 x 0.2 slab: one compound
    block whose convex parts sum to 1.75 m^3 (each part convex), with the slab one interface or
    more (the foot's bottom)."""
    V = np.array([[0, 0, 0], [2, 0, 0], [2, 0, 0.5], [0.5, 0, 0.5], [0.5, 0, 2], [0, 0, 2],
                  [0, 1, 0], [2, 1, 0], [2, 1, 0.5], [0.5, 1, 0.5], [0.5, 1, 2], [0, 1, 2]], dtype=float)
    V[:, 2] += 0.2
    front = [0, 1, 2, 3, 4, 5]  # y = 0, counter-clockwise seen from -y
    back = [11, 10, 9, 8, 7, 6]
    sides = [(0, 6, 7, 1), (1, 7, 8, 2), (2, 8, 9, 3), (3, 9, 10, 4), (4, 10, 11, 5), (5, 11, 6, 0)]
    f = _obj(tmp_path / "l.obj", [("slab", _box(-0.5, 2.5, -0.5, 1.5, 0, 0.2), _HEX_FACES),
                                 ("L", V, [front, back, *sides])])
    rc, scene = _import(tmp_path, f, "--fixed", "slab")
    assert rc == 0
    bl = {b["id"]: b for b in scene["blocks"]}
    assert "parts" in bl["L"] and len(bl["L"]["parts"]) >= 2
    from scipy.spatial import ConvexHull
    vols = [ConvexHull(np.array(p["vertices"])).volume for p in bl["L"]["parts"]]
    assert sum(vols) == pytest.approx(1.75, rel=1e-9)
    sc = load_scene(scene)
    assert sc.blocks[[b.id for b in sc.blocks].index("L")].volume == pytest.approx(1.75, rel=1e-9)
    assert len(find_interfaces(sc)) >= 1
    rec = scene["meta"]["import"]
    assert rec["compound_blocks"] == 1 and rec["hulls"] == 1


def test_open_mesh_rejected_naming_the_object(tmp_path, capsys):
    """A box missing its top face: exit 2, one line naming the object 'lid_missing'."""
    f = _obj(tmp_path / "open.obj", [("base", _box(0, 1, 0, 1, 0, 1), _HEX_FACES),
                                    ("lid_missing", _box(0, 1, 0, 1, 1, 2), _HEX_FACES[:1] + _HEX_FACES[2:])])
    rc, _ = _import(tmp_path, f)
    assert rc == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "lid_missing" in err[0] and "open" in err[0]


def test_repeated_faces_and_fixed_lowest(tmp_path):
    """Every face written twice (as compas_dem's dome does) is read once; --fixed-lowest fixes the two
    blocks standing at z = 0, not the one on top of them."""
    faces2 = _HEX_FACES + _HEX_FACES
    f = _obj(tmp_path / "two.obj", [("a", _box(0, 1, 0, 1, 0, 1), faces2), ("b", _box(1, 2, 0, 1, 0, 1), faces2),
                                   ("c", _box(0, 2, 0, 1, 1, 1.5), faces2)])
    rc, scene = _import(tmp_path, f, "--fixed-lowest")
    assert rc == 0
    assert sorted(b["id"] for b in scene["blocks"] if b.get("fixed")) == ["a", "b"]
    sc = load_scene(scene)
    assert sc.total_mass == pytest.approx(2000 * (1 + 1 + 1), rel=1e-9)


def test_compas_dem_wall_closes_its_25mm_joints(tmp_path):
    """compas_dem's wall.obj (38 boxes of 1 x 0.5 x 0.25 m, head joints drawn 25 mm open): every
    block convex, the largest gap closed 25 mm, and the scene loads."""
    from tests.conftest import ROOT
    rc, scene = _import(tmp_path, ROOT / "tests" / "data" / "import" / "wall.obj")
    assert rc == 0
    rec = scene["meta"]["import"]
    assert rec["blocks"] == 38 and rec["hulls"] == 38
    assert rec["largest_gap_closed_m"] == pytest.approx(0.025, abs=1e-9)
    assert rec["interfaces"] > 37  # at least a spanning set of 38 blocks


@pytest.mark.slow  # about 25 s: 90 curved voussoirs cut into convex parts
def test_compas_dem_dome_loads_as_compound_blocks(tmp_path):
    """compas_dem's dome.obj: 90 blocks, each face listed twice, curved hexagons: all compound, and the
    written scene loads with interfaces found."""
    from tests.conftest import ROOT
    rc, scene = _import(tmp_path, ROOT / "tests" / "data" / "import" / "dome.obj")
    assert rc == 0
    rec = scene["meta"]["import"]
    assert rec["blocks"] == 90 and rec["compound_blocks"] == 90
    assert rec["interfaces"] > 90
