"""A declared mirror symmetry (limit/verdict/symmetry.py) is checked, and the direction sweep uses it.

A second method for the mirrored half: the full 360-degree sweep of the same scene.
"""
import copy

import numpy as np
import pytest

from limit import load_scene
from limit.direction_sweep import sweep
from limit.verdict.symmetry import check_mirror
from scenes import builders as B


def _wall():
    return B.running_bond_wall(3, 3, dim=3, L=0.4, H=0.2, T=0.2, mu=0.8, name="w")


def test_a_symmetric_wall_passes_and_a_moved_block_is_named():
    data = _wall()
    check_mirror(load_scene(data))
    bad = copy.deepcopy(data)
    blk = [b for b in bad["blocks"] if not b.get("fixed")][-1]  # a top block
    blk["box"]["center"][1] += 0.01  # across the mirror plane (the load is along x): its image is 2 cm off
    with pytest.raises(ValueError, match=f"block '{blk['id']}' has no mirror image"):
        check_mirror(load_scene(bad))


def test_an_oblique_box_is_not_symmetric_about_its_load_plane():
    """A box 0.4 x 0.25 loaded along (1, 1)/sqrt(2): the vertical plane through that diagonal
    direction maps the box onto a box turned by 90 degrees (not itself; 0.4 != 0.25)."""
    data = B.single_block(3, 0.4, 1.0, t=0.25, mu=0.8)
    data["loads"]["live"] = [{"type": "body_force", "direction": [1.0, 1.0, 0.0]}]
    with pytest.raises(ValueError, match="no mirror image"):
        check_mirror(load_scene(data))


def test_a_declared_symmetry_halves_the_sweep_with_the_full_sweep_s_answer():
    data = dict(_wall(), symmetry="mirror")
    half = sweep(data, 30.0, jobs=1, frictional=False)
    full = sweep(data, 30.0, jobs=1, mirror=False, frictional=False)
    assert half["mirror"] and half["solved"] == 7 and full["solved"] == 12
    assert np.allclose(half["alpha"], full["alpha"], rtol=1e-6)
    lop = copy.deepcopy(data)
    lop["loads"]["live"] = [{"type": "body_force", "direction": [1.0, 1.0, 0.0]}]
    with pytest.raises(ValueError, match="no mirror image"):
        sweep(lop, 30.0, jobs=1, frictional=False)
