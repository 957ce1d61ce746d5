"""Generated scenes against collapse factors found without :mod:`limit`: the four-hinge mechanism
search (scenes/closed_forms.arch_hinge_alpha, virtual work over all hinge positions) for arches on
piers and between abutments, where sliding does not govern at mu = 0.8 (the alphas are far below
mu) so the associative LP must meet the hinging value; and walls' closed forms by virtual work
(overturning t / H across a 3D wall, the catalog's 5/14 in a 2D running-bond wall); the vaults' symmetry."""

import math

import pytest

from limit.analysis import analyse
from limit.model.scene import load_scene
from scenes import generators as G
from scenes.closed_forms import arch_reference
from scenes.generators.reference import chain_hinge_alpha


def _lp(d):
    res = analyse(load_scene(d), method="lp").data
    assert res["lp"]["status"] == "optimal"
    return res["lp"]["alpha"]


def _pier_chain(d):
    """The arch on piers as a chain from the base up the right pier, over the ring, down the left pier."""
    ids = [b["id"] for b in d["blocks"]]
    right = sorted(i for i in ids if i.startswith("pier-right-")) + ["skewback-right"]
    left = ["skewback-left"] + sorted((i for i in ids if i.startswith("pier-left-")), reverse=True)
    n = sum(i.startswith("v") for i in ids)
    return right + [f"v{k}" for k in range(n)] + left


@pytest.mark.parametrize("kw", [pytest.param(dict(kind="semicircular", n=7), marks=pytest.mark.slow),  # about 3 s
                                dict(kind="pointed", n=6),
                                pytest.param(dict(kind="segmental", n=7, rise=0.6), marks=pytest.mark.slow)],
                         ids=lambda kw: kw["kind"])
def test_arch_on_piers_four_hinge(kw):
    """The LP's alpha equals the least four-hinge mechanism of the chain base | pier courses |
    skewback | voussoirs | skewback | pier courses | base (hinges at either end of any four
    joints, the pier bases and course joints included), to 1e-6."""
    d = G.arch(pier_courses=2, mu=0.8, **kw)
    ref = chain_hinge_alpha(d, _pier_chain(d), "base", "base")
    assert ref["alpha"] < 0.5
    assert _lp(d) == pytest.approx(ref["alpha"], rel=1e-6)


@pytest.mark.slow  # about 2 s: the LP of a 3D arch on piers
def test_arch_on_piers_3d_meets_2d_reference():
    """The 3D arch is the 2D one extruded along y and loaded in its plane: the same four-hinge alpha."""
    d2 = G.arch("pointed", n=6, pier_courses=2)
    ref = chain_hinge_alpha(d2, _pier_chain(d2), "base", "base")["alpha"]
    assert _lp(G.arch("pointed", n=6, pier_courses=2, dim=3, depth=0.5)) == pytest.approx(ref, rel=1e-6)


def test_arch_between_abutments_meets_catalog_reference():
    """With fixed piers the semicircular arch of span s and thickness t is scenes.builders.arch's of
    centre-line radius R = (s + t)/2: closed_forms.arch_reference(n, R, t) (the catalog's arch reference)."""
    s, t, n = 2.0, 0.2, 9
    ref = arch_reference(n, (s + t) / 2, t)
    assert _lp(G.arch("semicircular", span=s, thickness=t, n=n, fixed_piers=True)) == pytest.approx(ref, rel=1e-6)


def test_aligned_barrel_vault_is_a_row_of_arches():
    """Unstaggered rings are independent arches loaded alike: the vault's alpha is the arch's,
    closed_forms.arch_reference(n, R, t) with R = (span + t)/2."""
    s, t, n = 2.0, 0.2, 7
    ref = arch_reference(n, (s + t) / 2, t)
    d = G.barrel_vault(span=s, thickness=t, n=n, rings=2, ring_width=0.3, stagger=False)
    assert _lp(d) == pytest.approx(ref, rel=1e-6)


def test_wall_out_of_plane_overturning():
    """A 3D running-bond wall loaded across (+y) overturns as a whole about its base edge:
    alpha = T / H (the catalog's wall-out-of-plane-3d closed form), 0.2 / 1.2."""
    d = G.wall(length=1.6, height=1.2, dim=3, mu=0.8)
    d["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]
    assert _lp(d) == pytest.approx(0.2 / 1.2, rel=1e-6)


def test_running_bond_wall_opening_joints_by_virtual_work():
    """A 2D running-bond wall 1.2 x 1.2 m of 0.4 x 0.4 m blocks (3 courses, the odd one with half
    blocks at its ends), mu = 1.2: the layout of the catalog's wall-3x3-opening-2d, whose frictional
    alpha is 5/14 by hand (tests/test_catalog.py: the right half block of course 1 and the block
    above it turn together about the toe (1.2, 0.4); dead-load work 0.08 x 0.1 + 0.16 x 0.2 = 0.04
    against live-load work 0.08 x 0.2 + 0.16 x 0.6 = 0.112 per unit rotation) and whose dilatant
    LP gives alpha_lp = 1, the value of the whole wall overturning about its toe (centroid 0.6 m
    from the toe and 0.6 m up)."""
    d = G.wall(length=1.2, height=1.2, unit=(0.4, 0.2, 0.4), mu=1.2)
    res = analyse(load_scene(d), method="auto").data
    assert res["lp"]["alpha"] == pytest.approx(1.0, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(5 / 14, rel=1e-4)


@pytest.mark.parametrize("build, turn_deg", [(lambda: G.cross_vault(n=6, segments=2), 90.0),
                                             (lambda: G.dome(meridians=8, rings=3), 45.0)],
                         ids=["cross-vault", "dome"])
def test_vault_and_dome_rotational_symmetry(build, turn_deg):
    """The cross vault is its own quarter turn about z, the dome of 8 meridians its own eighth turn:
    the live load turned by that angle meets the same alpha (a check of the webs' and rings'
    rotated copies, their joints and friction frames)."""
    d = build()
    a0 = _lp(d)
    t = math.radians(turn_deg)
    d["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(t), math.sin(t), 0.0]}]
    assert _lp(d) == pytest.approx(a0, rel=1e-5)
