"""limit/geom/_clip.py ``intersect`` against shapely (test extra, pinned in constraints.txt) and closed forms, on nearly
parallel edges. Lengths in m, tol = 1e-6 m unless told."""
import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from limit.geom._clip import intersect

TOL = 1e-6


def shoelace(p):
    """Signed area (m2, > 0 counter-clockwise) of a vertex list; 0 below three points."""
    if len(p) < 3:
        return 0.0
    q = np.roll(p, -1, axis=0)
    return 0.5 * float(np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))


def rotate(P, theta, c):
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    return (P - c) @ R.T + c


def convex(rng, k):
    """A counter-clockwise convex k-gon: points at sorted angles on an ellipse (semi-axes 0.15-1.5 m)."""
    ang = np.sort(rng.uniform(0.0, 2 * np.pi, k))
    return np.c_[np.cos(ang), np.sin(ang)] * rng.uniform(0.3, 1.0) * rng.uniform(0.5, 1.5, 2) \
        + rng.uniform(-0.5, 0.5, 2)


def nearly_parallel_pair(rng):
    """(A, B): A a random convex polygon; B A's mirror image across one of its edges (so the two
    share that edge's line), turned by 1e-12 to 1e-4 rad about the edge's midpoint and moved off
    the line by -0.5 to 2 tol (or by up to 0.2 m, overlapping or apart)."""
    k = int(rng.integers(3, 9))
    A = convex(rng, k)
    i = int(rng.integers(k))
    p, q = A[i], A[(i + 1) % k]
    d = (q - p) / np.linalg.norm(q - p)
    n = np.array([-d[1], d[0]])  # inward normal of A on edge i
    B = ((A - p) @ (np.eye(2) - 2 * np.outer(n, n)).T + p)[::-1]  # mirror, back to counter-clockwise
    B = rotate(B, 10 ** rng.uniform(-12, -4) * rng.choice([-1, 1]), (p + q) / 2)
    return A, B + n * rng.uniform(-0.5, 2.0) * TOL * rng.choice([1.0, 1e5])


def check_against_shapely(A, B, tol=TOL):
    """Area within tol x (perimeter A + perimeter B) of shapely's; every vertex inside A and B up to
    tol (the module's rule: within tol of a line counts as on it); counter-clockwise; no two consecutive
    vertices closer than tol; unless the intersection is a sliver (width area / diameter < 10 tol),
    every vertex of shapely's within 2 tol of ours (measured: 0.97 tol; in slivers up to 5.9 tol, where
    a crossing of nearly parallel edges is not computed and a vertex within tol of another is dropped)."""
    res = intersect(A[None], B[None], tol)[0]
    ref = Polygon(A).intersection(Polygon(B))
    per = Polygon(A).length + Polygon(B).length
    assert abs(shoelace(res) - ref.area) <= tol * per, (shoelace(res), ref.area)
    if len(res) < 3:
        return res
    assert shoelace(res) > 0
    assert np.all(np.linalg.norm(res - np.roll(res, 1, axis=0), axis=1) > tol)
    for P in (A, B):
        E = np.roll(P, -1, axis=0) - P
        inward = np.c_[-E[:, 1], E[:, 0]] / np.linalg.norm(E, axis=1)[:, None]
        dist = np.einsum("ijd,jd->ij", res[:, None, :] - P[None, :, :], inward)  # (vertex, edge)
        assert dist.min() >= -tol * (1 + 1e-9)
    if ref.geom_type == "Polygon" and ref.area > 10 * tol * np.linalg.norm(np.ptp(res, axis=0)):
        ours = Polygon(res)
        assert max(ours.distance(Point(v)) for v in ref.exterior.coords) <= 2 * tol
    return res


@pytest.mark.slow  # about 3-7 s: many nearly parallel pairs against shapely
def test_nearly_parallel_edges_against_shapely():
    """2000 pairs sharing an edge line up to a tilt of 1e-12 to 1e-4 rad and an offset of -0.5 to 2 tol."""
    rng = np.random.default_rng(21)
    n_area = 0
    for _ in range(2000):
        res = check_against_shapely(*nearly_parallel_pair(rng))
        n_area += len(res) >= 3
    assert 200 < n_area < 1900  # both outcomes (an area, no area) occur


@pytest.mark.slow  # about 3 s: random convex pairs against shapely
def test_random_convex_pairs_against_shapely():
    """1000 random convex pairs (3 to 8 vertices), and each polygon against itself turned by 1e-12 to
    1e-4 rad about a random point (every edge nearly parallel to one of the other's)."""
    rng = np.random.default_rng(7)
    for _ in range(1000):
        k = int(rng.integers(3, 9))
        A = convex(rng, k)
        check_against_shapely(A, convex(rng, int(rng.integers(3, 9))))
        check_against_shapely(A, rotate(A, 10 ** rng.uniform(-12, -4) * rng.choice([-1, 1]),
                                        A.mean(axis=0) + rng.uniform(-1, 1, 2)))


@pytest.mark.parametrize("delta", [-3e-6, -1e-6, -5e-7, 0.0, 5e-7, 1e-6, 3e-6, 1e-3])
def test_parallel_edges_overlap_closed_form(delta):
    """A = [0, 1]^2; B = [0.3, 1.3] x [delta - 1, delta]: parallel edges on y = 0 and y = delta. The
    overlap is 0.7 x max(delta, 0) m2; within tol the rule may count B's top as on A's bottom, so
    the area is within 0.7 tol of that (an offset below -tol: no area)."""
    A = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    B = np.array([[0.3, delta - 1.0], [1.3, delta - 1.0], [1.3, delta], [0.3, delta]])
    res = intersect(A[None], B[None], TOL)[0]
    assert abs(shoelace(res) - 0.7 * max(delta, 0.0)) <= 0.7 * TOL
    if delta < -TOL:
        assert len(res) < 3 or shoelace(res) <= 0.7 * TOL


@pytest.mark.parametrize("origin", [0.0, 1e3, 1e5])
def test_square_against_itself_turned_far_from_origin(origin):
    """The unit square at (origin, origin) and itself turned by 1e-10 rad about its centre: the
    corners move by at most 0.5 sqrt(2) 1e-10 m, so the exact intersection has area 1 within
    4 x 1e-10 m2 and lies within 1e-10 m of the square. Result: 1 within 4 tol, and every vertex within
    tol + 1e-10 of one of the 4 corners (no crossing of the nearly parallel edges is computed)."""
    A = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) + origin
    B = rotate(A, 1e-10, A.mean(axis=0))
    res = intersect(A[None], B[None], TOL)[0]
    assert shoelace(res) == pytest.approx(1.0, abs=4 * TOL)
    near = np.linalg.norm(res[:, None, :] - A[None, :, :], axis=2).min(axis=1)
    assert np.all(near <= TOL + 1e-10 + 1e-12 * origin), near


def test_vectorised_rows_are_independent():
    """m pairs in one call give the same polygons as m calls of one pair."""
    rng = np.random.default_rng(3)
    pairs = [nearly_parallel_pair(rng) for _ in range(40)]
    pairs = [(A, B) for A, B in pairs if len(A) == 5]
    assert len(pairs) >= 3
    many = intersect(np.array([A for A, _ in pairs]), np.array([B for _, B in pairs]), TOL)
    for (A, B), got in zip(pairs, many):
        one = intersect(A[None], B[None], TOL)[0]
        assert np.array_equal(one, got)
