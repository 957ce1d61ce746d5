"""Joint groups: the scene's ``joints`` list (limit/model/joint_groups.py) selects joints by
block pair or by tags and sets their friction (their cohesion and tension: tests/test_cohesion.py);
a selection of nothing, an unknown tag and a property the yield domain does not model are rejected,
naming the entry."""
import json

import numpy as np
import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene
from scenes import builders as B


def _stack():
    """Three 0.5 x 0.3 m blocks s0, s1, s2 (tags course-0..2) on a fixed base, mu 0.6."""
    return B.stack(3, dim=2, b=0.5, h=0.3, mu=0.6)


def test_a_damp_proof_course_by_tags_sets_the_sliding_load():
    """The joints between course 0 and course 1 get mu 0.2: the two blocks above slide on it when
    alpha (W1 + W2) = 0.2 (W1 + W2), alpha = 0.2, below overturning (the top two blocks about the
    toe of course 1: b / h = 0.5 / 0.6 = 0.83) and below sliding elsewhere (0.6). The DEM job
    carries the pair's friction."""
    d = _stack()
    d["joints"] = [{"between": {"tags": ["course-0", "course-1"]}, "mu": 0.2}]
    s = load_scene(d)
    res = analyse(s, method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(0.2, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(0.2, rel=1e-6)
    from dem_validation.job import _friction_pairs

    ids = {b.id: b.index for b in s.blocks}
    assert _friction_pairs(s, find_interfaces(s)) == [[ids["s0"], ids["s1"], 0.2]]


def test_later_entries_win_over_earlier_ones_and_over_interfaces_friction():
    d = _stack()
    d["interfaces"] = {"friction": [{"blocks": ["base", "s0"], "mu": 0.3}]}
    d["joints"] = [{"between": {"blocks": ["s0", "base"]}, "mu": 0.4},
                   {"between": {"tags": ["course-1", "course-2"]}, "mu": 0.5},
                   {"between": {"blocks": ["base", "s0"]}, "mu": 0.35}]
    s = load_scene(d)
    I = find_interfaces(s)
    mu = {tuple(sorted(p)): m for p, m in zip(I.pairs(s), I.mu)}
    assert mu == {("base", "s0"): 0.35, ("s0", "s1"): 0.6, ("s1", "s2"): 0.5}


@pytest.mark.parametrize("entry, match", [
    ({"between": {"blocks": ["s0", "s2"]}, "mu": 0.3}, r"joints\[0\]\.between: selects no joint: no interface "
                                                       r"between blocks 's0' and 's2'"),
    ({"between": {"tags": ["course-0", "course-2"]}, "mu": 0.3}, r"joints\[0\]\.between: selects no joint"),
    ({"between": {"tags": ["dpc", "course-1"]}, "mu": 0.3}, r"joints\[0\]\.between\.tags\[0\]: no block has the tag 'dpc'"),
    ({"between": {"blocks": ["s0", "nope"]}}, r"joints\[0\]\.between\.blocks\[1\]: unknown block id 'nope'"),
    ({"between": {"blocks": ["s0", "s1"]}, "fc": -2e6}, r"joints\[0\]\.fc: "),
    ({"between": {}}, r"joints\[0\]\.between: give"),
])
def test_mistakes_are_named(entry, match, tmp_path):
    d = _stack()
    d["joints"] = [entry]
    with pytest.raises(SceneError, match=match):
        analyse(load_scene(d), method="lp")
    path = tmp_path / "s.json"
    path.write_text(json.dumps(d))
    from limit.cli import main

    assert main(["solve", str(path), "--method", "lp"]) == 2


def test_zero_cohesion_is_accepted_and_changes_nothing():
    d = _stack()
    plain = analyse(load_scene(d), method="lp").data["lp"]["alpha"]
    d["joints"] = [{"between": {"tags": ["course-0", "course-1"]}, "cohesion": 0, "tensile_strength": 0}]
    assert analyse(load_scene(d), method="lp").data["lp"]["alpha"] == pytest.approx(plain, rel=1e-12)
    assert np.isfinite(plain)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_damp_proof_course_by_plane_selects_the_joints_that_lie_in_it(dim):
    """A plane selection (joints whose corners lie within the tolerance of the plane) on a
    running-bond wall picks exactly the joints between course 0 and course 1 that the tags
    selection picks (by construction the bed joint at z = H), and only those; the stack's plane
    at y = 0.3 gives the tags test's alpha = 0.2 (the blocks above slide on mu 0.2). A plane with
    no joint in it is rejected, naming it; the plane's point follows the scene's units."""
    up = [0.0, 1.0] if dim == 2 else [0.0, 0.0, 1.0]
    at = (lambda z: [0.0, z] if dim == 2 else [0.0, 0.0, z])
    wall = B.running_bond_wall(courses=3, per_course=3, dim=dim, L=0.4, H=0.175, mu=0.65)
    by_tags, by_plane = dict(wall), dict(wall)
    by_tags["joints"] = [{"between": {"tags": ["course-0", "course-1"]}, "mu": 0.3}]
    by_plane["joints"] = [{"between": {"plane": {"point": at(0.175), "normal": up}}, "mu": 0.3}]
    mu_t, mu_p = (find_interfaces(load_scene(x)).mu for x in (by_tags, by_plane))
    assert (mu_t == 0.3).sum() >= 3 and np.array_equal(mu_t, mu_p)
    d = _stack() if dim == 2 else B.stack(3, dim=3, b=0.5, h=0.3, mu=0.6)
    d["joints"] = [{"between": {"plane": {"point": at(0.3), "normal": up}}, "mu": 0.2}]
    assert analyse(load_scene(d), method="nlp").data["nlp"]["alpha"] == pytest.approx(0.2, rel=1e-6)
    d["joints"] = [{"between": {"plane": {"point": at(0.45), "normal": up}}, "mu": 0.2}]
    with pytest.raises(SceneError, match=r"joints\[0\]\.between: selects no joint: no interface lies in the plane"):
        analyse(load_scene(d), method="lp")
    from scenes.transform import transform

    mm = dict(transform(by_plane, s=1000.0), units="mm")  # the same wall in millimetres
    assert np.array_equal(find_interfaces(load_scene(mm)).mu, mu_p)
    R = np.array([[0.0, -1.0], [1.0, 0.0]]) if dim == 2 else np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0],
                                                                       [0.0, 0.0, 1.0]])
    turned = transform(by_plane, R=R, t=[0.3] * dim)  # the plane moves with the wall
    assert (find_interfaces(load_scene(turned)).mu == 0.3).sum() == (mu_p == 0.3).sum()
