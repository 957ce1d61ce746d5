"""Step 2 from the reversed load's collapse state, mirrored (limit.model.reversal_mirror and the
setting mirror_starts of limit.analysis)."""
import json
from pathlib import Path

import numpy as np
import pytest

from limit.analysis import analyse
from limit.geom.interfaces import find_interfaces
from limit.model import reversal_mirror
from limit.model.assemble import Options
from limit.model.scene import load_scene
from limit.model.turned_load import turned
from scenes import builders as B

ROOT = Path(__file__).resolve().parents[1]


def _mirror(data):
    scene = load_scene(data)
    return scene, reversal_mirror.find(scene, find_interfaces(scene))


def test_a_symmetric_stack_maps_onto_itself_and_motions_reflect():
    """A 3-block stack loaded along +x is symmetric about the plane x = its centre: every block is
    its own image, M = diag(-1, 1, 1). A block tipping towards +x about its +x toe moves its
    centroid by u = (1, 0, 0.2) while turning by w = (0, 0.5, 0) (about +y); its mirror image tips
    towards -x: u' = M u = (-1, 0, 0.2), and the rotation, a pseudovector, w' = -M w = (0, -0.5, 0)."""
    scene, m = _mirror(B.stack(3, dim=3, b=0.3, h=0.4, t=0.3, mu=0.8))
    assert m is not None
    assert list(m.image) == list(range(len(scene.blocks)))
    assert np.allclose(m.M, np.diag([-1.0, 1.0, 1.0]))
    bid = scene.blocks[scene.free[0]].id
    got = m.mechanism(scene, {bid: [1.0, 0.0, 0.2, 0.0, 0.5, 0.0]})
    assert got[bid] == pytest.approx([-1.0, 0.0, 0.2, 0.0, -0.5, 0.0])


def test_a_running_bond_wall_loaded_out_of_plane_pairs_nothing_but_itself_and_in_plane_swaps_its_ends():
    """Along +x (in its plane) the mirror swaps the wall's end blocks (c0-0 <-> c0-2); along +y
    (out of its plane) every block runs through the thickness and is its own image."""
    data = json.loads((ROOT / "scenes" / "catalog" / "wall-3x3-3d.json").read_text())
    scene, m = _mirror(data)
    ids = [b.id for b in scene.blocks]
    assert ids[m.image[ids.index("c0-0")]] == "c0-2"
    scene90, m90 = _mirror(turned(data, 90.0))
    assert list(m90.image) == list(range(len(scene90.blocks)))


def test_no_mirror_where_the_scene_or_its_loads_break_the_symmetry():
    """The oblique block's load at 30 deg from its axes (no block face across the load), a stack
    with a dead point force along the load (not mirrored into itself), and a stack with one joint's
    friction changed (the interfaces' strengths differ across the plane) have no reversal mirror."""
    assert _mirror(json.loads((ROOT / "scenes" / "catalog" / "block-oblique-3d.json").read_text()))[1] is None
    data = B.stack(3, dim=3, b=0.3, h=0.4, t=0.3, mu=0.8)
    pushed = json.loads(json.dumps(data))
    pushed["loads"]["dead"].append({"type": "point_force", "block": "s2", "force": [10.0, 0.0, 0.0],
                                    "point": [0.15, 0.15, 1.2]})
    assert _mirror(pushed)[1] is None
    wall = B.running_bond_wall(2, 3, dim=3, L=0.4, H=0.4, T=0.6, mu=1.2)
    assert _mirror(wall)[1] is not None  # symmetric until one joint's friction changes
    wall.setdefault("interfaces", {})["friction"] = [{"blocks": ["c0-0", "c1-0"], "mu": 0.5}]
    assert _mirror(wall)[1] is None


@pytest.mark.slow
def test_step_2_reaches_the_reversed_loads_state_through_the_mirror():
    """wall-3x3-3d loaded out of its plane (+y): the LP overturns the wall about its base edge,
    T / H = 0.5, and step 2 from its own starts stays there; under the reversed load (-y) it
    verifies a lower state. The wall is symmetric about its middle plane, so by that symmetry the
    two directions have the same frictional collapse states and alphas: with the mirror start step
    2 along +y reaches -y's alpha, below the LP's 0.5, and the point passes the frictional check."""
    data = json.loads((ROOT / "scenes" / "catalog" / "wall-3x3-3d.json").read_text())
    plus = load_scene(turned(data, 90.0))
    off = analyse(plus, options=Options(settings={"mirror_starts": False}), verdict=False).data["nlp"]
    assert off["alpha"] == pytest.approx(0.5, rel=1e-6)
    minus = analyse(load_scene(turned(data, 270.0)), options=Options(settings={"mirror_starts": False}),
                    verdict=False).data["nlp"]
    assert minus["status"] == "optimal" and minus["alpha"] < 0.5 * (1 - 1e-3)
    on = analyse(plus, verdict=False).data["nlp"]
    assert on["status"] == "optimal" and on["alpha"] == pytest.approx(minus["alpha"], rel=1e-7)
    [entry] = on["mirror_starts"]
    assert entry["adopted"] and entry["alpha_there"] == pytest.approx(minus["alpha"], rel=1e-7)
    assert on["verification"]["complementarity"] <= 1e-6
