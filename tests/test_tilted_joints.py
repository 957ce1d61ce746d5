"""Joints whose two faces are not exactly parallel (``interfaces.angle_tolerance``,
limit/geom/interfaces.py), and the import that writes the key (scenes/importers/gaps.py
``tilt_and_separation``, pipeline ``_tilted``).

A block of width b = 0.4 m and height h = 1 m stands on a fixed base whose top is the plane
z = 0. The block's bottom is tilted by theta = 0.2 deg, t = tan(theta): its bottom edge is
z = t x, so it touches the base along x = 0 and stands b t = 1.40 mm above it at x = b. The
coplanar test accepts about 0.081 deg only. With the scene's tolerance 2 mm (> b t) and
``angle_tolerance`` 0.5 deg (> theta), that is one joint.

Closed form of the rocking about the toe at x = b, per unit depth: the block is the trapezoid
between z = t x and z = h, of area A = b h - t b^2 / 2, centroid
x_c = (b^2 h / 2 - t b^3 / 3) / A and z_c = (b h^2 / 2 - t^2 b^3 / 6) / A. The interface lies in
the base's face plane moved halfway to the block's face centre, z_i = t b / 4
(limit/geom/interfaces.py), so the toe is (b, z_i) and moment equilibrium about it gives
alpha = (b - x_c) / (z_c - z_i). Sliding needs alpha = mu = 0.6, above it.
"""
import json

import numpy as np
import pytest

from limit.analysis import analyse
from limit.cli import main
from limit.errors import SceneError
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene

B_, H_, T_ = 0.4, 1.0, float(np.tan(np.radians(0.2)))


def _closed_form(b=B_, h=H_, t=T_):
    A = b * h - t * b ** 2 / 2
    xc = (b ** 2 * h / 2 - t * b ** 3 / 3) / A
    zc = (b * h ** 2 / 2 - t ** 2 * b ** 3 / 6) / A
    return (b - xc) / (zc - t * b / 4)


def _scene(dim, angle=None, t=T_, tol=2e-3):
    if dim == 3:
        base = [[x, y, z] for x in (-0.5, 0.9) for y in (0, 1) for z in (-0.3, 0)]
        blk = [[x, y, z] for x in (0, B_) for y in (0, 1) for z in (t * x, H_)]
        load = [1, 0, 0]
    else:
        base = [[-0.5, -0.3], [0.9, -0.3], [0.9, 0], [-0.5, 0]]
        blk = [[0, 0], [B_, t * B_], [B_, H_], [0, H_]]
        load = [1, 0]
    sc = {"format": "blockscene/1", "dim": dim, "friction": 0.6, "tolerance": tol,
          "blocks": [{"id": "base", "vertices": base, "fixed": True}, {"id": "block", "vertices": blk}],
          "loads": {"live": [{"type": "body_force", "direction": load}]}}
    if angle is not None:
        sc["interfaces"] = {"angle_tolerance": angle}
    return sc


@pytest.mark.parametrize("dim", [2, 3])
def test_a_tilted_joint_within_the_angle_tolerance_rocks_at_its_closed_form(dim):
    sc = load_scene(_scene(dim, angle=0.5))
    inter = find_interfaces(sc)
    assert len(inter) == 1
    assert inter.area[0] == pytest.approx(B_ * 1.0, rel=1e-5)  # the whole bottom (2D: 0.4 x thickness 1)
    assert analyse(sc, method="lp").data["lp"]["alpha"] == pytest.approx(_closed_form(), rel=1e-7)


@pytest.mark.parametrize("dim", [2, 3])
def test_without_the_key_the_tilted_block_touches_nothing(dim):
    assert len(find_interfaces(load_scene(_scene(dim)))) == 0
    with pytest.raises(SceneError, match="touches no other block"):
        analyse(load_scene(_scene(dim)), method="lp")


@pytest.mark.parametrize("dim", [2, 3])
def test_the_faces_must_meet_within_the_tolerance_over_the_whole_overlap(dim):
    """The same tilt with the tolerance 1 mm, below b t = 1.40 mm: no joint, though the angle passes
    and the face centres are only b t / 2 = 0.70 mm apart."""
    assert len(find_interfaces(load_scene(_scene(dim, angle=0.5, tol=1e-3)))) == 0


def test_the_import_takes_a_block_on_a_ridge_as_two_joints(tmp_path):
    """A fixed gable (ridge along y at x = 0, z = 0.5; its two roof faces fall by 1 deg to x = -1
    and x = 1) under a flat-bottomed block (x in [-0.2, 0.2]) that spans the ridge. The block's
    bottom matches both roof faces, but one face of a block joins one cluster only, so one
    pair is snapped to a common plane and the other keeps two planes about 1.5 deg apart (the
    snapped plane turns by half of 1 deg). The import measures that pair and writes
    ``interfaces.angle_tolerance`` and a tolerance that take it: two interfaces; without the
    angle key, one."""
    import trimesh

    from test_import_formats import _write_obj

    s = np.tan(np.radians(1.0))
    base = trimesh.convex.convex_hull(np.array([[x, y, z] for y in (0, 1) for x, z in
                                                ((-1, 0), (1, 0), (-1, 0.5 - s), (0, 0.5), (1, 0.5 - s))]))
    top = trimesh.creation.box(extents=[0.4, 1, 0.5])
    top.apply_translation([0, 0.5, 0.75])
    f = tmp_path / "ridge.obj"
    _write_obj(f, [base, top], ["gable", "block"])
    out = tmp_path / "ridge.json"
    assert main(["import", str(f), "--fixed", "gable", "-o", str(out)]) == 0
    sc = json.loads(out.read_text())
    tilted = sc["meta"]["import"]["tilted_joints"]
    assert tilted["count"] == 1 and 1.0 < tilted["largest_angle_deg"] < 2.0
    assert 1.0 < sc["interfaces"]["angle_tolerance"] <= 5.0
    assert len(find_interfaces(load_scene(sc))) == 2
    del sc["interfaces"]["angle_tolerance"]
    assert len(find_interfaces(load_scene(sc))) == 1
