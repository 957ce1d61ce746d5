"""Contact detection on assemblies counted by hand, and its invariance."""
import numpy as np
import pytest

from limit.geom.interfaces import find_interfaces
from limit.model.scene import load_scene
from scenes import builders as B
from scenes.transform import random_rotation, reorder, transform


def by_pair(scene, I):
    return {tuple(sorted(p)): k for k, p in enumerate(I.pairs(scene))}


def wall_expectations(T):
    """Interfaces of a 3-course, 3-block running-bond wall (L=0.4, H=0.175), by hand.

    Returns a list of (pair, contact length along the wall or height, centroid (x, z)).
    Course 0: 3 blocks; course 1: half, 2 full, half; course 2: 3 blocks.
    """
    L, H = 0.4, 0.175
    out = []
    for k in range(3):
        out.append((("base", f"c0-{k}"), L, (0.2 + k * L, 0.0)))
    for c, n in ((0, 3), (2, 3)):
        for k in range(n - 1):
            out.append(((f"c{c}-{k}", f"c{c}-{k+1}"), H, ((k + 1) * L, (c + 0.5) * H)))
    for k in range(3):
        out.append(((f"c1-{k}", f"c1-{k+1}"), H, (0.2 + k * L, 1.5 * H)))
    # Horizontal joints: 6 half-block overlaps between courses 0|1 and 1|2.
    for lower, upper, z in ((0, 1, H), (2, 1, 2 * H)):
        for j in range(6):
            lo_blk = f"c{lower}-{j // 2}"
            up_blk = f"c1-{(j + 1) // 2}"
            out.append(((lo_blk, up_blk), L / 2, (0.1 + 0.2 * j, z)))
    return out


@pytest.mark.parametrize("dim", [2, 3])
def test_running_bond_wall_by_hand(dim):
    T = 0.2
    s = load_scene(B.running_bond_wall(3, 3, dim=dim, L=0.4, H=0.175, T=T))
    I = find_interfaces(s)
    expect = wall_expectations(T)
    assert len(I) == len(expect) == 22
    pairs = by_pair(s, I)
    for pair, length, (x, z) in expect:
        k = pairs[tuple(sorted(pair))]
        area = length * (1.0 if dim == 2 else T)
        assert I.area[k] == pytest.approx(area, rel=1e-12), pair
        want = [x, z] if dim == 2 else [x, T / 2, z]
        assert np.allclose(I.centroid[k], want, atol=1e-12), pair
        assert I.is_rect[k]


@pytest.mark.parametrize("dim", [2, 3])
def test_portal(dim):
    s = load_scene(B.portal(dim=dim, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3))
    I = find_interfaces(s)
    assert sorted(map(tuple, map(sorted, I.pairs(s)))) == sorted(
        [("base", "col-left"), ("base", "col-right"), ("col-left", "lintel"), ("col-right", "lintel")])
    assert np.allclose(I.area, 0.3 * (1.0 if dim == 2 else 0.3))


@pytest.mark.parametrize("dim,n", [(2, 5), (2, 27), (3, 9)])
@pytest.mark.parametrize("span", [180.0, 120.0])
def test_arch_has_n_plus_one_interfaces(dim, n, span):
    R, t = 2.0, 0.3
    s = load_scene(B.arch(n, R=R, t=t, span_deg=span, dim=dim))
    I = find_interfaces(s)
    assert len(I) == n + 1
    area = t * (1.0 if dim == 2 else t)
    assert np.allclose(I.area, area, rtol=1e-9)
    # Joint centroids on the centre line at the joint angles.
    phi0 = np.radians(90 - span / 2)
    phis = np.linspace(phi0, np.pi - phi0, n + 1)
    c = I.centroid
    xz = c[:, [0, 1]] if dim == 2 else c[:, [0, 2]]
    assert np.allclose(np.linalg.norm(xz, axis=1), R, rtol=1e-9)
    assert np.allclose(np.sort(np.arctan2(xz[:, 1], xz[:, 0])), phis, atol=1e-9)


def test_normals_point_from_a_to_b_and_frames_are_right_handed():
    s = load_scene(B.corner_walls())
    I = find_interfaces(s)
    ca = np.array([s.blocks[i].centroid for i in I.a])
    cb = np.array([s.blocks[i].centroid for i in I.b])
    assert np.all(np.einsum("ij,ij->i", cb - ca, I.normal) > 0)
    assert np.allclose(np.cross(I.t1, I.t2), I.normal)
    assert np.allclose(np.einsum("ij,ij->i", I.t1, I.normal), 0)


def test_corner_walls_counts():
    """corner_walls(courses=2, len_a=2, len_b=2): L = 0.4, H = 0.2, T = L/2 = 0.2 m,
    XA = YB = T + 2 L = 1.0 m. Joints from _bond_edges (last block merged only if < L/4):

    course 0 (z 0-0.2): A0 x [0,.4] [.4,.8] [.8,1.0] (y 0-.2); B0 y [.2,.6] [.6,1.0] (x 0-.2)
    course 1 (z .2-.4): A1 x [.2,.6] [.6,1.0];                  B1 y [0,.4] [.4,.8] [.8,1.0]

    Face contacts (positive area; the line contacts, e.g. A1-0 over B0-0 at x = .2, do not count):
    base under course 0: 5 (areas .08 .08 .04 .08 .08 m2);
    course 0 head joints: A0-0|A0-1, A0-1|A0-2, B0-0|B0-1, and A0-0|B0-0 (face y = .2): 4;
    course 1 head joints: A1-0|A1-1, B1-0|B1-1, B1-1|B1-2, and A1-0|B1-0 (face x = .2): 4;
    bed joint 0|1: A1-0 on A0-0, A0-1; A1-1 on A0-1, A0-2; B1-0 on A0-0 (corner square)
    and B0-0; B1-1 on B0-0, B0-1; B1-2 on B0-1: 9.
    Total 5 + 4 + 4 + 9 = 22; every contact but the base ones is 0.2 x 0.2 = 0.04 m2.
    """
    s = load_scene(B.corner_walls(courses=2, len_a=2, len_b=2))
    I = find_interfaces(s)
    big = {("base", "A0-0"), ("base", "A0-1"), ("base", "B0-0"), ("base", "B0-1")}
    expect = big | {("base", "A0-2"),
                    ("A0-0", "A0-1"), ("A0-1", "A0-2"), ("B0-0", "B0-1"), ("A0-0", "B0-0"),
                    ("A1-0", "A1-1"), ("B1-0", "B1-1"), ("B1-1", "B1-2"), ("A1-0", "B1-0"),
                    ("A0-0", "A1-0"), ("A0-1", "A1-0"), ("A0-1", "A1-1"), ("A0-2", "A1-1"),
                    ("A0-0", "B1-0"), ("B0-0", "B1-0"), ("B0-0", "B1-1"), ("B0-1", "B1-1"), ("B0-1", "B1-2")}
    expect = {tuple(sorted(p)) for p in expect}
    assert len(expect) == 22
    assert s.n_blocks == 1 + 5 + 5
    assert len(I) == 22
    got = by_pair(s, I)
    assert set(got) == expect
    for pair, k in got.items():
        assert I.area[k] == pytest.approx(0.08 if pair in {tuple(sorted(q)) for q in big} else 0.04, rel=1e-9)


def test_fixed_fixed_contacts_ignored():
    d = B.single_block(dim=2)
    d["blocks"].append({"id": "wall", "box": {"center": [-0.5, 0.5], "size": [0.4, 1.0]}, "fixed": True})
    s = load_scene(d)
    I = find_interfaces(s)
    assert I.pairs(s) == [("base", "block")]


def test_non_rectangular_contact():
    # A triangular prism standing on its triangle: triangular contact, area 0.5 * 0.4 * 0.3.
    d = B.single_block(dim=3)
    d["blocks"][1] = {"id": "prism", "vertices": [[0, 0, 0], [0.4, 0, 0], [0, 0.3, 0],
                                                  [0, 0, 1], [0.4, 0, 1], [0, 0.3, 1]]}
    s = load_scene(d)
    I = find_interfaces(s)
    assert len(I) == 1 and not I.is_rect[0]
    assert I.area[0] == pytest.approx(0.06)
    assert np.allclose(I.centroid[0], [0.4 / 3, 0.1, 0.0])
    assert len(I.local[0]) == 3


def test_partial_overlap_3d():
    d = B.single_block(dim=3, b=0.3, h=0.5)
    d["blocks"].append({"id": "top", "box": {"center": [0.25, 0.2, 0.6], "size": [0.3, 0.3, 0.2]}})
    s = load_scene(d)
    I = find_interfaces(s)
    k = by_pair(s, I)[("block", "top")]
    # top covers x in [0.1, 0.4], y in [0.05, 0.35]; the block [0, 0.3]^2: overlap 0.2 x 0.25
    assert I.area[k] == pytest.approx(0.2 * 0.25)
    assert np.allclose(I.centroid[k], [0.2, 0.175, 0.5])
    assert I.is_rect[k]
    assert I.l1[k] == pytest.approx(0.125) and I.l2[k] == pytest.approx(0.1)
    assert np.allclose(np.abs(I.t1[k]), [0, 1, 0])


def test_edge_contact_is_not_an_interface():
    d = B.single_block(dim=3, b=0.3, h=0.5)
    d["blocks"].append({"id": "diag", "box": {"center": [0.45, 0.45, 0.6], "size": [0.3, 0.3, 0.2]}})
    s = load_scene(d)
    I = find_interfaces(s)
    assert ("block", "diag") not in by_pair(s, I)


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_invariance_rigid_motion_and_scale(dim, seed):
    rng = np.random.default_rng(seed)
    base = B.running_bond_wall(4, 3, dim=dim)
    s0 = load_scene(base)
    I0 = find_interfaces(s0)
    R = random_rotation(dim, rng)
    t = rng.uniform(-100, 100, dim)
    for scale in (1.0, 1000.0, 0.001):
        moved = reorder(transform(base, R, t, scale), seed)
        s1 = load_scene(moved)
        I1 = find_interfaces(s1)
        assert len(I1) == len(I0)
        p0, p1 = by_pair(s0, I0), by_pair(s1, I1)
        assert p0.keys() == p1.keys()
        for pair, k0 in p0.items():
            k1 = p1[pair]
            assert I1.area[k1] == pytest.approx(I0.area[k0] * scale**2, rel=1e-9)
            assert np.allclose(I1.centroid[k1], scale * I0.centroid[k0] @ R.T + t, rtol=1e-9,
                               atol=1e-9 * scale * s0.scale + 1e-9 * np.abs(t).max())
            assert I1.l1[k1] == pytest.approx(I0.l1[k0] * scale, rel=1e-9)
