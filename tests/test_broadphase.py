"""limit/geom/_broadphase.py (sweep and prune) against brute force and a lattice count by hand."""
import numpy as np
import pytest

from limit.geom._broadphase import candidate_pairs


def brute(lo, hi, tol):
    """All pairs i < j whose boxes overlap or touch within tol on every axis (O(n^2), the definition)."""
    n = len(lo)
    return {(i, j) for i in range(n) for j in range(i + 1, n)
            if np.all(lo[j] <= hi[i] + tol) and np.all(lo[i] <= hi[j] + tol)}


def as_set(a, b):
    pairs = list(zip(a.tolist(), b.tolist()))
    assert len(pairs) == len(set(pairs)), "a pair reported twice"
    assert all(i < j for i, j in pairs)
    return set(pairs)


def random_boxes(seed):
    """n boxes (2 to 80) in 2D or 3D, corners in [0, 3] m, sizes cubed uniforms in [0, 1] m
    (many thin boxes, some far larger than their neighbours)."""
    rng = np.random.default_rng(seed)
    d, n = int(rng.integers(2, 4)), int(rng.integers(2, 81))
    lo = rng.uniform(0.0, 3.0, (n, d))
    return lo, lo + rng.uniform(0.0, 1.0, (n, d)) ** 3


@pytest.mark.parametrize("chunk", [1, 7, 2_000_000])
@pytest.mark.parametrize("tol", [0.0] + [pytest.param(t, marks=pytest.mark.slow) for t in (1e-3, 0.05)])  # 1.5-2 s each
def test_random_boxes_match_brute_force(tol, chunk):
    """60 random scenes: exactly the brute-force pairs. chunk = 1 and 7 run the chunk loop once per
    sweep position or few (chunk = 1 also when one position alone has more candidates than chunk)."""
    split = 0
    for seed in range(60):
        lo, hi = random_boxes(seed)
        expect = brute(lo, hi, tol)
        assert as_set(*candidate_pairs(lo, hi, tol, chunk=chunk)) == expect, seed
        split += len(expect) > 3 * 7  # more pairs than 3 chunks of 7 candidates: >= 3 passes of the loop
    assert split >= 10


@pytest.mark.parametrize("chunk", [1, 5, 2_000_000])
@pytest.mark.parametrize("shape", [(1, 7), (4, 5), (3, 3, 3), (2, 4, 5)])
def test_touching_lattice_count(shape, chunk):
    """Unit cells of an a x b (x c) lattice (1 m, exact binary coordinates: ties in the sort and
    contacts at exactly tol = 0). Cells p, q touch (face, edge or corner) iff |p_k - q_k| <= 1 on every
    axis; per axis there are 3a - 2 ordered pairs (x, x') with |x - x'| <= 1, so the number of
    touching pairs is (prod(3 a_k - 2) - prod(a_k)) / 2: 1 x 7: (1*19 - 7) / 2 = 6 (a chain);
    4 x 5: (10*13 - 20) / 2 = 55 (= 15 + 16 side pairs + 2*3*4 corner pairs); 3 x 3 x 3:
    (343 - 27) / 2 = 158; 2 x 4 x 5: (4*10*13 - 40) / 2 = 240."""
    expected = {(1, 7): 6, (4, 5): 55, (3, 3, 3): 158, (2, 4, 5): 240}[shape]
    cells = np.array(np.meshgrid(*[np.arange(a) for a in shape], indexing="ij")).reshape(len(shape), -1).T
    lo = cells.astype(float)
    perm = np.random.default_rng(len(cells)).permutation(len(cells))  # not in lattice order
    lo = lo[perm]
    got = as_set(*candidate_pairs(lo, lo + 1.0, 0.0, chunk=chunk))
    assert len(got) == expected
    assert got == brute(lo, lo + 1.0, 0.0)
    # a gap of 1e-9 m between all cells (cells 1 - 1e-9 wide): no pair at tol 0, all of them back at tol 1e-8
    assert not len(candidate_pairs(lo, lo + 1.0 - 1e-9, 0.0, chunk=chunk)[0])
    assert len(as_set(*candidate_pairs(lo, lo + 1.0 - 1e-9, 1e-8, chunk=chunk))) == expected


@pytest.mark.parametrize("tol", [pytest.param(-1e-3, marks=pytest.mark.slow), -0.05,  # about 1.5 s each
                                 pytest.param(-0.2, marks=pytest.mark.slow)])
def test_negative_tolerance_misses_no_overlap(tol):
    """tol < 0 (limit/geom/overlap.py: boxes overlapping by more than |tol|): no overlapping pair is missed.
    Measured: the sweep also returns pairs in which a box is thinner than |tol| along the sweep axis
    (the reverse test lo_i <= hi_j + tol is not made on that axis); each such extra pair must have a
    box thinner than |tol| on some axis. The narrow phase of overlap.py filters them."""
    for seed in range(60):
        lo, hi = random_boxes(seed)
        expect = brute(lo, hi, tol)
        for chunk in (1, 2_000_000):
            got = as_set(*candidate_pairs(lo, hi, tol, chunk=chunk))
            assert expect <= got, (seed, sorted(expect - got)[:5])
            for i, j in got - expect:
                assert np.any(np.minimum(hi[i] - lo[i], hi[j] - lo[j]) < -tol), (seed, i, j)


def test_fewer_than_two_boxes():
    for n in (0, 1):
        a, b = candidate_pairs(np.zeros((n, 3)), np.ones((n, 3)), 0.0)
        assert len(a) == len(b) == 0
