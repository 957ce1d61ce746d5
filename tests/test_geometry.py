"""Block geometry against hand-computed volumes, centroids and normals."""
import numpy as np
import pytest

from limit.geom import geometry
from limit.model.scene import load_scene
from scenes import builders as B


def check_faces(poly):
    for n, off, face in zip(poly.face_normals, poly.face_offsets, poly.faces):
        assert np.isclose(np.linalg.norm(n), 1.0)
        assert np.allclose(face @ n, off, atol=1e-12)             # face points on their plane
        assert np.all(poly.vertices @ n <= off + 1e-12)            # block inside
        assert poly.centroid @ n < off                             # outward
        if poly.dim == 3:                                          # counter-clockwise about n
            c = face.mean(axis=0)
            cr = np.cross(face - c, np.roll(face, -1, axis=0) - c).sum(axis=0)
            assert cr @ n > 0


def test_box_3d():
    p = geometry.box([1, 2, 3], [2, 4, 6])
    assert p.measure == pytest.approx(48.0)
    assert np.allclose(p.centroid, [1, 2, 3])
    assert len(p.faces) == 6
    check_faces(p)


def test_rotated_box_3d_matches_hull():
    R = geometry.rotation_matrix(3, 33.0, [1, 2, 3])
    p = geometry.box([0.5, 0, 1], [0.3, 0.7, 1.1], R)
    q = geometry.polyhedron(p.vertices)
    assert q.measure == pytest.approx(0.3 * 0.7 * 1.1, rel=1e-12)
    assert np.allclose(q.centroid, [0.5, 0, 1])
    assert len(q.faces) == 6 and all(len(f) == 4 for f in q.faces)
    check_faces(p)
    check_faces(q)


def test_tetrahedron():
    p = geometry.polyhedron([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    assert p.measure == pytest.approx(1 / 6)
    assert np.allclose(p.centroid, [0.25, 0.25, 0.25])
    assert len(p.faces) == 4
    check_faces(p)


def test_polygon_2d_trapezoid():
    # Trapezoid: area (2 + 1)/2 * 1 = 1.5; centroid y = h (b + 2a) / (3 (a + b)) with a=1 (top), b=2.
    p = geometry.polygon([[0, 0], [2, 0], [1.5, 1], [0.5, 1]])
    assert p.measure == pytest.approx(1.5)
    assert np.allclose(p.centroid, [1.0, (2 + 2) / 9])
    check_faces(p)


def test_point_on_an_edge_is_accepted_and_dropped():
    p = geometry.polygon([[0, 0], [1, 0], [2, 0], [2, 1], [0, 1]])
    assert p.measure == pytest.approx(2.0)
    assert len(p.vertices) == 4


def test_rotated_box_2d():
    p = geometry.box([1, 1], [2, 1], geometry.rotation_matrix(2, 30))
    assert p.measure == pytest.approx(2.0)
    assert np.allclose(p.centroid, [1, 1])
    check_faces(p)


def test_block_mass_2d_and_3d():
    s2 = load_scene(B.single_block(dim=2, b=0.3, h=1.0) | {"thickness": 0.5, "density": 2400})
    blk = s2.blocks[1]
    assert blk.volume == pytest.approx(0.3 * 1.0 * 0.5)
    assert blk.mass == pytest.approx(2400 * 0.15)
    s3 = load_scene(B.single_block(dim=3, b=0.3, h=1.0, t=0.2))
    assert s3.blocks[1].mass == pytest.approx(2000 * 0.3 * 1.0 * 0.2)
    assert np.allclose(s3.blocks[1].centroid, [0.15, 0.1, 0.5])


def test_per_block_density():
    d = B.stack(2, dim=3)
    d["blocks"][2]["density"] = 500.0
    s = load_scene(d)
    assert s.blocks[2].mass == pytest.approx(500 * 0.3 * 0.3 * 0.5)
    assert s.blocks[1].mass == pytest.approx(2000 * 0.3 * 0.3 * 0.5)


def test_polygon_area_centroid_one_and_stacked():
    from limit.geom.geometry import polygon_area_centroid

    sq = np.array([[1.0, 2.0], [3.0, 2.0], [3.0, 3.0], [1.0, 3.0]])  # CCW 2 x 1 rectangle
    a, c = polygon_area_centroid(sq)
    assert isinstance(a, float) and a == 2.0 and np.allclose(c, [2.0, 2.5])
    assert polygon_area_centroid(sq[::-1])[0] == -2.0  # clockwise: negative
    tri = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0], [0.0, 3.0]])  # a repeated vertex adds nothing
    A, C = polygon_area_centroid(np.stack([sq, tri]))
    assert A.shape == (2,) and C.shape == (2, 2)
    assert np.allclose(A, [2.0, 4.5]) and np.allclose(C, [[2.0, 2.5], [1.0, 1.0]])


def test_plane_basis_one_and_stacked():
    from limit.geom.geometry import plane_basis

    rng = np.random.default_rng(3)
    n = rng.normal(size=(20, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    E1, E2 = plane_basis(n)
    for k in range(len(n)):
        e1, e2 = plane_basis(n[k])
        assert np.allclose(e1, E1[k], rtol=0, atol=1e-15) and np.allclose(e2, E2[k], rtol=0, atol=1e-15)
        assert np.allclose(np.cross(e1, e2), n[k]) and abs(e1 @ n[k]) < 1e-15 and np.isclose(e1 @ e1, 1.0)
