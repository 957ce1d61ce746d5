"""Compound blocks (a block with ``parts``: convex pieces that move as one rigid body), in the
scene reader, the contact search and the limit analysis.

The closed form: an L-shaped block standing on a fixed base, its foot [0, 1] x [0, 0.2] on the
base and its leg [0, 0.2] x [0.2, 1.0] on the foot (2D, metres). Areas 0.2 and 0.16, centroids
(0.5, 0.1) and (0.1, 0.6), so the block's centroid is x_c = (0.2*0.5 + 0.16*0.1)/0.36 = 29/90,
y_c = (0.2*0.1 + 0.16*0.6)/0.36 = 29/90. Under a horizontal body force along -x it overturns
about its left toe (0, 0): the live moment alpha W y_c equals the dead one W x_c, so
alpha = (horizontal distance from the toe to the centroid) / (the centroid's height) = x_c / y_c
= 1 exactly. Along +x it turns about the right toe (1, 0): alpha = (1 - x_c) / y_c = 61/29.
With mu = 3 sliding (alpha = mu) does not govern either way.
"""
import copy

import numpy as np
import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene

FOOT = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.2], [0.0, 0.2]]
LEG = [[0.0, 0.2], [0.2, 0.2], [0.2, 1.0], [0.0, 1.0]]


def l_block_2d(direction=-1.0, mu=3.0) -> dict:
    return {"format": "blockscene/1", "name": "l-block", "dim": 2, "friction": mu,
            "blocks": [{"id": "base", "box": {"center": [0.5, -0.1], "size": [3.0, 0.2]}, "fixed": True},
                       {"id": "L", "parts": [{"vertices": FOOT}, {"vertices": LEG}]}],
            "loads": {"live": [{"type": "body_force", "direction": [direction, 0.0]}]}}


def extrude(poly2d, depth=0.5):
    return [[x, y, z] for x, z in poly2d for y in (0.0, depth)]


def l_block_3d(direction=-1.0, mu=3.0) -> dict:
    return {"format": "blockscene/1", "name": "l-block-3d", "dim": 3, "friction": mu,
            "blocks": [{"id": "base", "box": {"center": [0.5, 0.25, -0.1], "size": [3.0, 1.5, 0.2]}, "fixed": True},
                       {"id": "L", "parts": [{"vertices": extrude(FOOT)}, {"vertices": extrude(LEG)}]}],
            "loads": {"live": [{"type": "body_force", "direction": [direction, 0.0, 0.0]}]}}


def test_mass_and_centroid_of_the_union():
    """Mass = density x (0.2 + 0.16) m^2 x 1 m thickness; centroid (29/90, 29/90) (module docstring)."""
    s = load_scene(l_block_2d())
    L = s.blocks[1]
    assert len(L.parts) == 2 and len(L.pieces) == 2
    assert L.mass == pytest.approx(2000.0 * 0.36, rel=1e-12)
    np.testing.assert_allclose(L.centroid, [29 / 90, 29 / 90], rtol=1e-12)


def test_contacts_between_parts_of_other_blocks_only():
    """The foot touches the base along [0, 1] (length 1 m); the leg touches only the foot, a part of
    its own block, which gives no interface."""
    I = find_interfaces(load_scene(l_block_2d()))
    assert len(I) == 1
    assert I.area[0] == pytest.approx(1.0)


@pytest.mark.parametrize("builder", [l_block_2d, l_block_3d])
@pytest.mark.parametrize("direction, alpha", [(-1.0, 1.0), (1.0, 61 / 29)])
def test_l_block_overturns_at_the_closed_form(builder, direction, alpha):
    res = analyse(load_scene(builder(direction)), method="nlp")
    assert res["lp"]["status"] == "optimal"
    assert res["lp"]["alpha"] == pytest.approx(alpha, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(alpha, rel=1e-6)


def test_a_box_split_into_parts_is_the_box():
    """A 0.4 x 1.2 block on a base (mu 0.6), whole or cut into three stacked parts, carries the
    same live load: rocking alpha = b/h = 1/3 (below mu)."""
    whole = l_block_2d(1.0, 0.6)
    whole["blocks"][1] = {"id": "B", "box": {"center": [0.2, 0.6], "size": [0.4, 1.2]}}
    cut = copy.deepcopy(whole)
    cut["blocks"][1] = {"id": "B", "parts": [
        {"vertices": [[0, y0], [0.4, y0], [0.4, y1], [0, y1]]} for y0, y1 in ((0, 0.3), (0.3, 0.8), (0.8, 1.2))]}
    a_whole = analyse(load_scene(whole), method="lp")["lp"]["alpha"]
    a_cut = analyse(load_scene(cut), method="lp")["lp"]["alpha"]
    assert a_whole == pytest.approx(1 / 3, rel=1e-6)
    assert a_cut == pytest.approx(a_whole, rel=1e-9)


def test_two_blocks_touching_through_two_parts_have_two_interfaces():
    """A block C = [0.2, 1.0] x [0.2, 0.6] laid on the L's foot, beside its leg, touches both
    parts: one interface along the foot's top (length 0.8 m) and one against the leg (0.4 m)."""
    d = l_block_2d()
    d["blocks"].append({"id": "C", "box": {"center": [0.6, 0.4], "size": [0.8, 0.4]}})
    I = find_interfaces(load_scene(d))
    assert sorted(zip(I.a.tolist(), I.b.tolist())) == [(0, 1), (1, 2), (1, 2)]
    assert sorted(I.area[I.b == 2].tolist()) == pytest.approx([0.4, 0.8])


def test_overlapping_parts_are_rejected_naming_the_part():
    d = l_block_2d()
    d["blocks"][1]["parts"][1]["vertices"] = [[0.0, 0.1], [0.2, 0.1], [0.2, 1.0], [0.0, 1.0]]
    with pytest.raises(SceneError, match=r"'L' \(part 0\) and 'L' \(part 1\) overlap"):
        load_scene(d)


def test_a_part_that_is_not_convex_names_the_part():
    d = l_block_2d()
    d["blocks"][1]["parts"][0]["vertices"] = FOOT + [[0.5, 0.1]]
    with pytest.raises(SceneError, match=r"block 'L'\)\.parts\[0\]: .*not convex"):
        load_scene(d)


def test_parts_and_box_together_are_rejected():
    d = l_block_2d()
    d["blocks"][1]["box"] = {"center": [0, 0], "size": [1, 1]}
    with pytest.raises(SceneError, match="exactly one of 'box', 'vertices' or 'parts'"):
        load_scene(d)
