"""scenes.generators: volumes and interface counts by construction, tags, parameter errors and
``limit build``. Lengths in m, volumes in m^3 (2D: area x the scene's thickness)."""
import json
import math

import numpy as np
import pytest

from limit.errors import SceneError
from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene
from scenes import generators as G

from tests.conftest import run_module


def _free_volume(d):
    sc = load_scene(d)
    return sum(b.volume for b in sc.blocks if not b.fixed)


def _n_interfaces(d):
    return len(find_interfaces(load_scene(d)))


def _tags(d, bid):
    return set(next(b for b in d["blocks"] if b["id"] == bid).get("tags", []))


# ----------------------------------------------------------------------------
# Arches


def test_semicircular_arch_volume_and_count():
    """Span s = 2, t = 0.25, n = 11, piers 0.5 wide x 1.5 high in 3 courses. Each voussoir is the
    quadrilateral between radii ri = 1 and re = 1.25 over an angle pi/n with flat chords: area
    (re^2 - ri^2) sin(pi/n) / 2; each pier w x hp (its top is the level springing joint). The chain
    base | 3 courses | 11 voussoirs | 3 courses | base has 3 + 1 + 10 + 1 + 3 = 18 joints."""
    d = G.arch("semicircular", span=2.0, thickness=0.25, n=11, pier_height=1.5, pier_width=0.5, pier_courses=3)
    ring = 11 * (1.25 ** 2 - 1.0) * math.sin(math.pi / 11) / 2
    assert _free_volume(d) == pytest.approx(ring + 2 * 0.5 * 1.5, rel=1e-12)
    assert _n_interfaces(d) == 18
    assert {"voussoir", "ring", "springing"} <= _tags(d, "v0") and "springing" in _tags(d, "v10")
    assert "key" in _tags(d, "v5") and "key" not in _tags(d, "v4")
    assert {"pier", "pier-right", "course-2", "skewback"} <= _tags(d, "skewback-right")
    assert {"pier", "pier-left", "course-0"} <= _tags(d, "pier-left-0")


def test_segmental_arch_skewback_volume():
    """Segmental, s = 2, rise f = 0.5: ri = (s^2/4 + f^2) / 2f = 1.25, the springing at phi0 =
    asin((ri - f)/ri) from the horizontal; n = 9 voussoirs over pi - 2 phi0. Each skewback adds
    above the pier's level top the area w t sin(phi0) less the triangle t cos(phi0) t sin(phi0) / 2
    between the inclined joint and the pier's face."""
    s, f, t, n, w, hp = 2.0, 0.5, 0.25, 9, 0.5, 1.5
    d = G.arch("segmental", span=s, rise=f, thickness=t, n=n, pier_width=w, pier_height=hp, pier_courses=2)
    ri = (s * s / 4 + f * f) / (2 * f)
    phi0 = math.asin((ri - f) / ri)
    ring = n * ((ri + t) ** 2 - ri ** 2) * math.sin((math.pi - 2 * phi0) / n) / 2
    wedge = w * t * math.sin(phi0) - t * math.cos(phi0) * t * math.sin(phi0) / 2
    assert _free_volume(d) == pytest.approx(ring + 2 * (w * hp + wedge), rel=1e-12)
    assert _n_interfaces(d) == 2 * 2 + n + 1


def test_pointed_arch_crown_and_count():
    """Pointed (equilateral: radius r = span = 2), n = 10. Each half's centre lies on the springing
    line r - s/2 = 1 beyond the crown, so the intrados meets x = 0 at the angle acos(1/r) above it
    (height r sin(60 deg) = sqrt(3) above the springing) and the extrados at acos(1/(r + t)); the
    crown joint joins them. Fixed piers: 11 joints."""
    r, t, hp = 2.0, 0.25, 1.5
    d = G.arch("pointed", span=2.0, thickness=t, n=10, pier_height=hp, fixed_piers=True)
    J = G.arch_joints("pointed", 2.0, t, 10, spring=hp)
    assert J[5, 0] == pytest.approx([0.0, hp + math.sqrt(3)], abs=1e-12)
    assert J[5, 1] == pytest.approx([0.0, hp + (r + t) * math.sin(math.acos(1.0 / (r + t)))], abs=1e-12)
    assert _n_interfaces(d) == 11
    assert "key" in _tags(d, "v4") and "key" in _tags(d, "v5")


def test_arch_3d_is_the_2d_outline_extruded():
    """3D over depth 0.4: every voussoir's volume is its 2D area times 0.4 (the 2D scene's thickness is 1)."""
    d2 = G.arch("segmental", n=7)
    d3 = G.arch("segmental", n=7, dim=3, depth=0.4)
    assert _free_volume(d3) == pytest.approx(0.4 * _free_volume(d2), rel=1e-12)
    assert _n_interfaces(d3) == _n_interfaces(d2)


@pytest.mark.parametrize("kw, name", [(dict(kind="gothic"), "kind"), (dict(kind="pointed", n=7), "n"),
                                      (dict(pier_width=0.1), "pier_width"), (dict(span=-1), "span"),
                                      (dict(kind="segmental", rise=1.5), "rise"), (dict(dim=4), "dim"),
                                      (dict(mu=-0.1), "mu"), (dict(density=0), "density"), (dict(n=2.5), "n")])
def test_arch_parameter_errors(kw, name):
    with pytest.raises(SceneError, match=f"^{name}"):
        G.arch(**kw)


# ----------------------------------------------------------------------------
# Walls


@pytest.mark.parametrize("bond, length, expected", [
    # running, 3 x 0.4 m: course 0 [0, .4, .8, 1.2] (3 blocks), course 1 joints at .2, .6, 1.0 (4 blocks).
    # base|course 0: 3; head joints 2 + 3; bed joints: the 4 upper blocks over 1, 2, 2, 1 lower ones = 6.
    ("running", 1.2, 3 + 2 + 3 + 6),
    # English, 0.8 m: stretchers [0, .4, .8]; headers from a queen closer, joints .1, .3, .5, .7 (5 blocks).
    # base 2; head joints 1 + 4; bed: [0,.1] [.1,.3] over s0, [.3,.5] over both, [.5,.7] [.7,.8] over s1 = 6.
    ("english", 0.8, 2 + 1 + 4 + 6),
    # Flemish, 1.2 m: H [0,.2] S [.2,.6] H [.6,.8] S [.8,1.2]; course 1 shifted by (L + W)/2 = .3: S [0,.3]
    # H [.3,.5] S [.5,.9] H [.9,1.1] and a closer [1.1,1.2] (W/2, kept). base 4; head joints 3 + 4;
    # bed: [0,.3] over H, S; [.3,.5] over S; [.5,.9] over S, H, S; [.9,1.1] and [1.1,1.2] over S = 8.
    ("flemish", 1.2, 4 + 3 + 4 + 8),
])
def test_wall_bond_counts_2d(bond, length, expected):
    """Two courses of unit (L, W, H) = (0.4, 0.2, 0.2); the counts derived in the parameters' comments.
    Volume: length x 0.4 x thickness (W for running bond, L otherwise)."""
    d = G.wall(length=length, height=0.4, bond=bond)
    assert _n_interfaces(d) == expected
    T = 0.2 if bond == "running" else 0.4
    assert _free_volume(d) == pytest.approx(length * 0.4 * T, rel=1e-12)


def test_wall_english_3d_counts():
    """English bond, 3D, 0.8 m long, 2 courses, thickness L = 0.4: course 0 is two wythes of two
    stretchers (4 blocks), course 1 five headers through the wall. base|course 0: 4; course 0: 1
    head joint per wythe + 2 collar joints (front|back of each stretcher pair) = 4; course 1: 4
    head joints; bed: the 6 header-over-stretcher pairs of the 2D elevation, each with both
    wythes = 12."""
    d = G.wall(length=0.8, height=0.4, bond="english", dim=3)
    assert _n_interfaces(d) == 4 + 4 + 4 + 12
    assert _free_volume(d) == pytest.approx(0.8 * 0.4 * 0.4, rel=1e-12)
    assert {"course-1", "header"} <= _tags(d, "c1-0") and {"stretcher", "front"} <= _tags(d, "c0-0f")


def test_wall_opening_with_lintel_counts():
    """Running bond, 1.2 x 0.6 m (3 courses), an opening 0.4 wide at x = 0.4, one course high, its
    lintel [0.2, 1.0] (bearing 0.2) in course 1. Course 0: [0, .4] and [.8, 1.2]; course 1: [0, .2],
    the lintel, [1.0, 1.2]; course 2: 3 stretchers. base: 2; head joints: 0 + 2 + 2; bed joints
    0|1: each course-0 block under its end piece and the lintel = 4; 1|2: [0,.2] and [1,1.2] under
    one block each, the lintel under all 3 = 5. Volume: (1.2 x 0.6 - 0.4 x 0.2) x 0.2."""
    d = G.wall(length=1.2, height=0.6, openings=[{"x": 0.4, "width": 0.4, "sill": 0.0, "height": 0.2}],
               lintel_bearing=0.2)
    assert _n_interfaces(d) == 2 + 4 + 4 + 5
    assert _free_volume(d) == pytest.approx((1.2 * 0.6 - 0.4 * 0.2) * 0.2, rel=1e-12)
    assert {"lintel", "opening-0"} <= _tags(d, "lintel-0")


@pytest.mark.parametrize("bond, dim", [("running", 2), ("english", 3), ("flemish", 3)])
def test_wall_openings_volume(bond, dim):
    """A lintelled window and a door under a flat arch: the blocks fill the wall less the two
    openings exactly, (3.2 x 1.6 - 0.8 x 0.6 - 0.8 x 0.8) x T; the flat arch's 5 voussoirs touch
    each other in a row (4 joints) and its springers touch the wall."""
    ops = [{"x": 0.4, "width": 0.8, "sill": 0.4, "height": 0.6}, {"x": 2.0, "width": 0.8, "sill": 0.0,
                                                                    "height": 0.8, "head": "arch"}]
    d = G.wall(length=3.2, height=1.6, bond=bond, dim=dim, openings=ops)
    T = 0.2 if bond == "running" else 0.4
    assert _free_volume(d) == pytest.approx((3.2 * 1.6 - 0.48 - 0.64) * T, rel=1e-12)
    sc = load_scene(d)
    pairs = {tuple(sorted(p)) for p in find_interfaces(sc).pairs(sc)}
    assert all(("arch-1-%d" % k, "arch-1-%d" % (k + 1)) in pairs for k in range(4))
    for k in (0, 4):
        assert any(f"arch-1-{k}" in p and any(q.startswith("c") for q in p) for p in pairs)


@pytest.mark.parametrize("bond, dim", [("running", 2), ("flemish", 3)])
def test_wall_round_arch_opening(bond, dim):
    """A door 0.8 wide, 0.6 to its springing, under a round arch in a 3.2 x 1.6 m wall (courses of
    0.2 m). The ring's extrados vertices lie on course lines: K = round(0.4/0.2 + 1) = 3 courses,
    extrados radius 3 x 0.2 / cos(15 deg), joints at asin(k 0.2 / re) (k = 0..3) on each side and a
    key of 30 degrees with a level top at 0.6 + 0.6 m. The blocks fill the wall less the door and
    the semicircle's chord polygon (the sum of r^2 sin(step)/2 over the 7 voussoirs' angle steps,
    r = 0.4); the key carries the course above; each springer rests on the wall."""
    re = 0.6 / math.cos(math.radians(15))
    steps = [math.asin(0.2 * k / re) for k in range(4)]
    angles = np.diff(steps).tolist()
    angles = angles + [math.radians(30)] + angles[::-1]
    void = sum(0.4 ** 2 * math.sin(a) / 2 for a in angles)
    d = G.wall(length=3.2, height=1.6, bond=bond, dim=dim,
               openings=[{"x": 1.2, "width": 0.8, "sill": 0.0, "height": 0.6, "head": "round"}])
    T = 0.2 if bond == "running" else 0.4
    assert _free_volume(d) == pytest.approx((3.2 * 1.6 - 0.8 * 0.6 - void) * T, rel=1e-12)
    sc = load_scene(d)
    key = next(b for b in sc.blocks if b.id == "arch-0-3")
    top = key.poly.vertices[:, sc.dim - 1].max()
    assert top == pytest.approx(1.2, abs=1e-12) and "key" in key.tags
    pairs = find_interfaces(sc).pairs(sc)
    assert any("arch-0-3" in p and any(q.startswith("c6-") for q in p) for p in pairs)
    for k in (0, 6):
        assert any(f"arch-0-{k}" in p and any(q.startswith("c2-") for q in p) for p in pairs)


@pytest.mark.parametrize("kw, name", [
    (dict(height=0.5), "height"), (dict(bond="stack"), "bond"), (dict(unit=(0.4, 0.2)), "unit"),
    (dict(openings=[{"x": 0.4, "width": 0.8, "sill": 0.1, "height": 0.6}]), r"openings\[0\].sill"),
    (dict(openings=[{"x": 0.0, "width": 0.8, "sill": 0.0, "height": 0.6}]), r"openings\[0\]"),
    (dict(openings=[{"x": 0.4, "width": 0.4, "height": 0.4}, {"x": 1.0, "width": 0.4, "height": 0.4}]),
     r"openings\[1\]"),
    (dict(openings=[{"x": 0.4, "width": 0.4, "height": 0.4}, {"x": 0.85, "width": 0.4, "height": 0.4}],
          lintel_bearing=0), "openings"),
    (dict(arch_voussoirs=4), "arch_voussoirs")])
def test_wall_parameter_errors(kw, name):
    with pytest.raises(SceneError, match=f"^{name}"):
        G.wall(**kw)


def test_corner_counts():
    """Corner, unit (0.4, 0.2, 0.2), wall A 0.6 m, wall B 0.4 m beyond A's back face, 2 courses.
    Course 0: A [0,.4] [.4,.6] (y 0-.2), B x 0-.2 y [.2,.6]. Course 1: A [.2,.6]; B through,
    y [0,.4] [.4,.6]. base: 3; course 0: A|A, A0|B = 2; course 1: A|B0, B0|B1 = 2; bed: A0 under
    A' and B'0, A1 under A', B0 under B'0 and B'1 = 5. Volume: (0.6 x 0.2 + 0.2 x 0.4) x 0.4."""
    d = G.wall_corner(length=0.6, length_b=0.4, height=0.4)
    assert _n_interfaces(d) == 3 + 2 + 2 + 5
    assert _free_volume(d) == pytest.approx((0.6 * 0.2 + 0.2 * 0.4) * 0.4, rel=1e-12)
    assert {"branch", "B", "course-1"} <= _tags(d, "B-c1-0")


def test_buttress_counts():
    """A wall 1.2 m long, 2 courses of (0.4, 0.2, 0.2), one buttress 0.4 wide at x = 0.4 standing
    0.4 out. Course 0: the wall through, [0,.4] [.4,.8] [.8,1.2]; the buttress abuts it, one block
    y .2-.6. Course 1: the wall stops at the buttress, [0,.2] [.2,.4] and [.8,1] [1,1.2]; the
    buttress runs through, y [0,.4] [.4,.6]. base: 4; course 0: 2 head joints + the middle block
    against the buttress = 3; course 1: 2 head joints, the through block against the wall each side
    and against the buttress's second block = 5; bed: [0,.4] under two, [.4,.8] under the through
    block, [.8,1.2] under two, the buttress block under both of course 1's = 7."""
    d = G.buttressed_wall(length=1.2, height=0.4, buttresses=(0.4,), width=0.4, depth=0.4)
    assert _n_interfaces(d) == 4 + 3 + 5 + 7
    assert _free_volume(d) == pytest.approx((1.2 * 0.2 + 0.4 * 0.4) * 0.4, rel=1e-12)


def test_corner_compound_quoins():
    """The corner of test_corner_counts with compound quoins: course 0's A [0,.4] and B y [.2,.6]
    become quoin-c0, course 1's B y [0,.4] and A [.2,.6] quoin-c1. Touching pairs: base with
    quoin-c0 and with A [.4,.6]; quoin-c0 with A [.4,.6] (head joint); quoin-c1 with B [.4,.6];
    bed: quoin-c0 with quoin-c1 and with B [.4,.6], A [.4,.6] with quoin-c1: 7."""
    d = G.wall_corner(length=0.6, length_b=0.4, height=0.4, compound_quoins=True)
    assert _touching_pairs(d) == {("base", "quoin-c0"), ("base", "c0-1"), ("c0-1", "quoin-c0"),
                                  ("B-c1-1", "quoin-c1"), ("quoin-c0", "quoin-c1"), ("B-c1-1", "quoin-c0"),
                                  ("c0-1", "quoin-c1")}
    assert _free_volume(d) == pytest.approx((0.6 * 0.2 + 0.2 * 0.4) * 0.4, rel=1e-12)
    assert "quoin" in _tags(d, "quoin-c1")


def test_tee_and_buttress_volumes_and_interlock():
    """T: 2.4 x 0.2 plus the stem 0.2 x 1.6, 1.2 high. Buttressed wall: 3.2 x 0.2 plus two 0.4 x 0.4
    buttresses, 1.6 high. In every odd course the stem's (buttress's) first block runs through the
    main wall (y from 0), in every even one it starts at the back face y = 0.2."""
    d = G.wall_tee()
    assert _free_volume(d) == pytest.approx((2.4 * 0.2 + 0.2 * 1.6) * 1.2, rel=1e-12)
    b = G.buttressed_wall()
    assert _free_volume(b) == pytest.approx((3.2 * 0.2 + 2 * 0.4 * 0.4) * 1.6, rel=1e-12)
    for sc, label in ((d, "B"), (b, "buttress0")):
        for c in range(6):
            blk = next(x for x in sc["blocks"] if x["id"] == f"{label}-c{c}-0")
            y0 = blk["box"]["center"][1] - blk["box"]["size"][1] / 2
            assert y0 == pytest.approx(0.0 if c % 2 else 0.2, abs=1e-12)
    with pytest.raises(SceneError, match="^at"):
        G.wall_tee(at=0.0)
    with pytest.raises(SceneError, match=r"^buttresses\[1\]"):
        G.buttressed_wall(buttresses=(0.4, 0.6))


# ----------------------------------------------------------------------------
# Vaults and dome


def test_barrel_vault_counts_and_volume():
    """n = 9 voussoirs over pi, ri = 1, re = 1.2, 4 rings 0.3 wide. Staggered: rings 0 and 2 have 9
    voussoirs (8 joints), rings 1 and 3 have 8 and two halves (10 pieces, 9 joints); each voussoir
    of an even ring overlaps two pieces of its odd neighbour: 2 n = 18 per ring face, 3 faces;
    each ring's two springers rest on the abutments: 8. Aligned: 4 x 8 + 3 x 9 + 8. Volume per ring
    ((re^2 - ri^2)/2) (sum of sin(angle) over its pieces) x 0.3."""
    n, ri, re, b = 9, 1.0, 1.2, 0.3
    d = G.barrel_vault(span=2.0, thickness=0.2, n=n, rings=4, ring_width=b)
    assert _n_interfaces(d) == 2 * 8 + 2 * 9 + 3 * 2 * n + 8
    k = (re ** 2 - ri ** 2) / 2 * b
    full, half = math.sin(math.pi / n), math.sin(math.pi / n / 2)
    assert _free_volume(d) == pytest.approx(k * (2 * n * full + 2 * ((n - 1) * full + 2 * half)), rel=1e-12)
    a = G.barrel_vault(span=2.0, thickness=0.2, n=n, rings=4, ring_width=b, stagger=False)
    assert _n_interfaces(a) == 4 * 8 + 3 * 9 + 8
    assert _free_volume(a) == pytest.approx(k * 4 * n * full, rel=1e-12)
    assert {"voussoir", "ring-1", "springing"} <= _tags(d, "r1-0") and "key" in _tags(d, "r0-4")


def _web_volume(ri, re, n, X):
    """Volume of one web of the cross vault, independently: course k's cross-section Q_k (the
    quadrilateral between radial lines at k pi/n and (k+1) pi/n, chords at ri and re, in the (y, z)
    plane) runs along x from the groin x = |y| to X, so its volume is X area(Q_k) - |first moment of
    Q_k about y = 0| (n even: no course crosses y = 0)."""
    tot = 0.0
    for k in range(n):
        a0, a1 = k * math.pi / n, (k + 1) * math.pi / n
        P = np.array([[ri * math.cos(a0), ri * math.sin(a0)], [re * math.cos(a0), re * math.sin(a0)],
                      [re * math.cos(a1), re * math.sin(a1)], [ri * math.cos(a1), ri * math.sin(a1)]])
        x, y = P[:, 0], P[:, 1]
        cr = x * np.roll(y, -1) - np.roll(x, -1) * y
        A = cr.sum() / 2
        Sy = ((x + np.roll(x, -1)) * cr).sum() / 6  # integral of the horizontal coordinate over Q_k
        tot += X * abs(A) - abs(Sy)
    return tot


@pytest.mark.parametrize("segments, stagger", [(1, False), (3, True)])
def test_cross_vault_volume_and_count(segments, stagger):
    """span 2, t 0.2 (ri 1, re 1.2 = X, the half side of the plan), n = 8 courses per barrel.
    Volume: 4 webs (_web_volume), however the courses are cut. One segment per course: 4 x 8
    blocks; in each web 7 joints between courses; on each of the 4 groin planes course k of one
    web meets the mirrored course of the next, n/2 = 4 faces each; the 2 springing courses of each
    web rest on the corner piers: 8. Total 4 x 7 + 4 x 4 + 8."""
    d = G.cross_vault(span=2.0, thickness=0.2, n=8, segments=segments, stagger=stagger)
    assert _free_volume(d) == pytest.approx(4 * _web_volume(1.0, 1.2, 8, 1.2), rel=1e-9)
    if segments == 1:
        assert _n_interfaces(d) == 4 * 7 + 4 * 4 + 8
    sc = load_scene(d)
    touching = {i for pair in find_interfaces(sc).pairs(sc) for i in pair}
    assert touching == {b.id for b in sc.blocks}  # every block, the piers included, has a joint


def _touching_pairs(d):
    """The distinct pairs of touching blocks: independent of how a compound block's contacts with
    one neighbour are grouped into interfaces (per piece pair, or per plane)."""
    sc = load_scene(d)
    return {tuple(sorted(p)) for p in find_interfaces(sc).pairs(sc)}


def test_cross_vault_compound_groins():
    """compound_groins, n = 8, one segment: each of the 4 groins joins n/2 pairs (course k of one
    web, course 7 - k of the next), so 4 x 8 blocks become 16 compound blocks of 2 parts.
    Touching pairs: along a groin, compounds k and k + 1 touch twice (a course joint in each web),
    3 pairs per groin = 12; each web's crown joint (y = 0 in its frame) joins two groins' crown
    compounds, 4 more; each pier carries one compound, 4: 20 pairs. The volume is unchanged."""
    d = G.cross_vault(span=2.0, thickness=0.2, n=8, segments=1, compound_groins=True)
    sc = load_scene(d)
    free = [b for b in sc.blocks if not b.fixed]
    assert len(free) == 16 and all(len(b.parts) == 2 for b in free)
    assert len(_touching_pairs(d)) == 12 + 4 + 4
    assert _free_volume(d) == pytest.approx(4 * _web_volume(1.0, 1.2, 8, 1.2), rel=1e-9)
    assert {"groin", "web-east", "web-north", "course-0", "course-7"} <= _tags(d, "groin-east-0")


def _dome_voussoir_volume(ri, re, lats, lons):
    """A voussoir's faces all lie on planes through the sphere's centre O or on its flat intrados
    and extrados, the extrados the intrados scaled by re/ri about O: its volume is the pyramid
    from O over the extrados less that over the intrados, (re^3 - ri^3) (|det(p1, p2, p3)| +
    |det(p1, p3, p4)|) / 6 with p the trapezoid's corners on the unit sphere."""
    p = [np.array([math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)])
         for la, lo in ((lats[0], lons[0]), (lats[0], lons[1]), (lats[1], lons[1]), (lats[1], lons[0]))]
    unit = abs(np.linalg.det(np.array([p[0], p[1], p[2]]))) + abs(np.linalg.det(np.array([p[0], p[2], p[3]])))
    return (re ** 3 - ri ** 3) * unit / 6


@pytest.mark.parametrize("oculus", [False, True])
def test_dome_counts_and_volume(oculus):
    """12 meridians x 4 rings, ri 1.5, re 1.7, rings of 90/5 degrees. Each ring: 12 meridian
    joints (a closed ring); 3 bed joints x 12 between rings; ring 0 on the base: 12; the cap on
    ring 3: 12 (none with an oculus). Cap volume: the pyramid from O over its extrados (triangles
    from the pole (0, 0, re) to the extrados circle) less that over its flat intrados polygon."""
    nm, nr, ri, re = 12, 4, 1.5, 1.7
    d = G.dome(span=3.0, thickness=0.2, meridians=nm, rings=nr, oculus=oculus)
    assert _n_interfaces(d) == nr * nm + (nr - 1) * nm + nm + (0 if oculus else nm)
    step, dl = math.pi / 2 / (nr + 1), 2 * math.pi / nm
    vol = nm * sum(_dome_voussoir_volume(ri, re, (j * step, (j + 1) * step), (0, dl)) for j in range(nr))
    if not oculus:
        top = nr * step
        e = [np.array([re * math.cos(top) * math.cos(k * dl), re * math.cos(top) * math.sin(k * dl),
                       re * math.sin(top)]) for k in range(2)]
        pole = np.array([0, 0, re])
        ext = nm * abs(np.linalg.det(np.array([e[0], e[1], pole]))) / 6
        rc = ri * math.cos(top)
        intr = nm * rc * rc * math.sin(dl) / 2 * (ri * math.sin(top)) / 3
        vol += ext - intr
    assert _free_volume(d) == pytest.approx(vol, rel=1e-12)
    assert {"voussoir", "ring-0", "meridian-3", "springing"} <= _tags(d, "ring0-3")


def test_vault_and_dome_errors():
    with pytest.raises(SceneError, match="^n"):
        G.cross_vault(n=7)
    with pytest.raises(SceneError, match="^meridians"):
        G.dome(meridians=2)
    with pytest.raises(SceneError, match="^rise"):
        G.barrel_vault(kind="segmental", rise=1.0)


# ----------------------------------------------------------------------------
# Every generator


@pytest.mark.parametrize("kind", sorted(G.GENERATORS))
def test_default_scene_is_sound(kind):
    """Each generator's default scene loads in strict mode (no key the schema does not know), every
    block has a joint, the default loads are self weight and 1 g along +x, and the associative LP
    finds a mechanism with 0 < alpha < 1; the parameters recorded in meta.generator rebuild it."""
    import warnings

    from limit.analysis import analyse

    d = G.GENERATORS[kind]()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc = load_scene(d, strict=True)
    assert d["loads"]["dead"] == [{"type": "self_weight"}]
    assert d["loads"]["live"] == [{"type": "body_force", "direction": [1.0] + [0.0] * (sc.dim - 1)}]
    touching = {i for pair in find_interfaces(sc).pairs(sc) for i in pair}
    assert touching == {b.id for b in sc.blocks}
    res = analyse(sc, method="lp").data
    assert res["lp"]["status"] == "optimal" and 0 < res["lp"]["alpha"] < 1
    assert G.GENERATORS[kind](**d["meta"]["generator"]) == d  # meta.generator rebuilds the scene


# ----------------------------------------------------------------------------
# limit build


@pytest.mark.slow  # about 3 s: limit build end to end in subprocesses
def test_build_writes_a_scene(tmp_path):
    """Exit 0, the file is the generator's dict for the same parameters."""
    out = tmp_path / "a.json"
    p = run_module("limit", "build", "arch", "--kind", "pointed", "--n", "8", "--pier-courses", "2",
                   "--fixed-piers", "-o", out)
    assert p.returncode == 0, p.stderr
    assert json.loads(out.read_text()) == json.loads(json.dumps(G.arch("pointed", n=8, pier_courses=2,
                                                                        fixed_piers=True)))
    out = tmp_path / "w.json"
    p = run_module("limit", "build", "wall", "--bond", "flemish", "--dim", "3", "--unit", "0.4", "0.2", "0.2",
                   "--opening", "0.4", "0.8", "0.4", "0.6", "--opening", "2.0", "0.8", "0", "0.8", "arch",
                   "--length", "3.2", "--height", "1.6", "-o", out)
    assert p.returncode == 0, p.stderr
    assert load_scene(out).n_blocks == len(json.loads(out.read_text())["blocks"])


@pytest.mark.parametrize("args, start", [  # a subprocess each, about 1 s
    (["arch", "--kind", "pointed", "--n", "7"], "error: n:"),
    pytest.param(["wall", "--length", "x"], "error: --length:", marks=pytest.mark.slow),
    pytest.param(["dome", "--meridians", "2"], "error: meridians:", marks=pytest.mark.slow),
    pytest.param(["wall", "--opening", "0.4", "0.8"], "error: --opening:", marks=pytest.mark.slow)])
def test_build_bad_option_exit_2(tmp_path, args, start):
    p = run_module("limit", "build", *args, "-o", tmp_path / "x.json")
    assert p.returncode == 2
    assert p.stderr.startswith(start) and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert not (tmp_path / "x.json").exists()
