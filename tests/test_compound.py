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
    res = analyse(load_scene(builder(direction)), method="nlp").data
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
    a_whole = analyse(load_scene(whole), method="lp").data["lp"]["alpha"]
    a_cut = analyse(load_scene(cut), method="lp").data["lp"]["alpha"]
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


def compound_springer_arch(n=9, R=1.0, t=0.15, mu=1.0) -> dict:
    """:func:`scenes.builders.arch` with its two springers compound: voussoirs v0 + v1 and
    v{n-2} + v{n-1} each one block of two convex parts (their union's intrados is concave)."""
    from scenes import builders as B

    d = B.arch(n=n, R=R, t=t, mu=mu, name="arch-compound-springers")
    by_id = {b["id"]: b for b in d["blocks"]}
    merged = {"springer-right": ("v0", "v1"), "springer-left": (f"v{n - 2}", f"v{n - 1}")}
    gone = {v for pair in merged.values() for v in pair}
    d["blocks"] = [b for b in d["blocks"] if b["id"] not in gone] + [
        {"id": sid, "parts": [{"vertices": by_id[v]["vertices"]} for v in pair], "tags": ["springer"]}
        for sid, pair in merged.items()]
    return d


def compound_springer_reference(n=9, R=1.0, t=0.15) -> float:
    """The four-hinge mechanism method (scenes.closed_forms.arch_hinge_alpha, independent of the
    limit analysis) on the same arch with the joints v0|v1 and v{n-2}|v{n-1} removed: each
    springer is one body of the two voussoirs' joint ends, summed weight and weighted centroid."""
    import math

    from limit.geom.geometry import polygon_area_centroid
    from scenes.closed_forms import arch_hinge_alpha

    ri, re = R - t / 2, R + t / 2
    phis = np.linspace(0.0, math.pi, n + 1)
    J = np.array([[[ri * math.cos(p), ri * math.sin(p)], [re * math.cos(p), re * math.sin(p)]] for p in phis])
    C, W = [], []
    for k in range(n):
        A, c = polygon_area_centroid(np.array([J[k, 0], J[k, 1], J[k + 1, 1], J[k + 1, 0]]))
        C.append(c)
        W.append(abs(A))
    C, W = np.array(C), np.array(W)

    def merge(i, j):
        return (W[i] * C[i] + W[j] * C[j]) / (W[i] + W[j]), W[i] + W[j]

    (c0, w0), (c1, w1) = merge(0, 1), merge(n - 2, n - 1)
    joints = np.concatenate([J[:1], J[2:n - 1], J[n:]])
    cents = np.vstack([c0, C[2:n - 2], c1])
    weights = np.concatenate([[w0], W[2:n - 2], [w1]])
    return arch_hinge_alpha(joints, cents, weights)["alpha"]


def test_compound_springers_arch_hinges_at_the_closed_form():
    """With mu = 1 no joint slides: the LP and step 2 equal the four-hinge mechanism method on the
    arch whose springer joints cannot hinge, which lies above the plain arch's value."""
    from scenes.closed_forms import arch_reference

    ref = compound_springer_reference()
    assert ref > arch_reference(9, 1.0, 0.15) * 1.001
    res = analyse(load_scene(compound_springer_arch()), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(ref, rel=1e-5)
    assert res["nlp"]["alpha"] == pytest.approx(ref, rel=1e-5)


def test_figures_and_vtk_draw_each_part_moving_with_the_block(tmp_path):
    """The mechanism drawing moves both parts of the L by the block's rigid motion: the corner
    (0, 0.2) that the foot and the leg share lands on the same point in both; the VTK file has one
    polygon per 2D piece (the base's and the L's two)."""
    from reports.plots import _moved, mechanism_figure
    from reports.vtk import write_vtk

    s = load_scene(l_block_2d())
    res = analyse(s, method="lp").data
    mech = res["lp"]["mechanism"]
    foot, leg = _moved(s, mech, 0.1)[1]
    k_foot = int(np.argmin(np.linalg.norm(s.blocks[1].parts[0].vertices - [0.0, 0.2], axis=1)))
    k_leg = int(np.argmin(np.linalg.norm(s.blocks[1].parts[1].vertices - [0.0, 0.2], axis=1)))
    np.testing.assert_allclose(foot[k_foot], leg[k_leg], atol=1e-12)
    assert not np.allclose(foot[k_foot], [0.0, 0.2])  # it did move
    assert mechanism_figure(s, res, None, tmp_path / "m.png") and (tmp_path / "m.png").stat().st_size > 1000
    text = write_vtk(s, {"lp_mechanism": mech}, tmp_path / "m.vtk").read_text()
    assert "POLYGONS 3 " in text


@pytest.mark.parametrize("dim", [2, 3])
def test_coplanar_contacts_of_one_block_pair_merge_into_one_interface(dim):
    """An L lying on its side, parts [0, 0.4] x [0, 1] and [0.4, 1] x [0, 0.2], both on the base:
    one joint along y = 0 from x = 0 to 1 (2D: length 1 m x thickness 1 m; 3D: 1 m x 0.5 m, a
    rectangle), centred at x = 0.5, rather than one interface per part. Then the low part is
    shortened to [0.4, 0.8] and moved to [0.5, 0.9]: the joint's polygon spans the hull [0, 0.9],
    its area is the 0.8 m in touch (x thickness or depth)."""
    tall = [[0.0, 0.0], [0.4, 0.0], [0.4, 1.0], [0.0, 1.0]]
    low = [[0.4, 0.0], [1.0, 0.0], [1.0, 0.2], [0.4, 0.2]]
    d = l_block_2d() if dim == 2 else l_block_3d()
    d["blocks"][1]["parts"] = [{"vertices": p if dim == 2 else extrude(p)} for p in (tall, low)]
    I = find_interfaces(load_scene(d))
    assert len(I) == 1
    assert I.area[0] == pytest.approx(1.0 if dim == 2 else 0.5)
    assert I.centroid[0][0] == pytest.approx(0.5)
    assert bool(I.is_rect[0])
    low = [[0.5, 0.0], [0.9, 0.0], [0.9, 0.2], [0.5, 0.2]]
    d["blocks"][1]["parts"][1] = {"vertices": low if dim == 2 else extrude(low)}
    I = find_interfaces(load_scene(d))
    assert len(I) == 1
    assert I.area[0] == pytest.approx(0.8 if dim == 2 else 0.4)
    assert np.ptp(np.asarray(I.polygons[0])[:, 0]) == pytest.approx(0.9)
