"""The dimension constants (limit.model.dims) against hand values."""
import numpy as np

from limit.model import dims


def test_layout_by_hand():
    """2D: (V, N, M), N at 1, moments from 2; 3D: (V1, V2, N, M1, M2, T), N at 2, moments from 3."""
    assert (dims.ndof(2), dims.normal_index(2), dims.first_moment_index(2)) == (3, 1, 2)
    assert (dims.ndof(3), dims.normal_index(3), dims.first_moment_index(3)) == (6, 2, 3)


def test_rigid_velocity_by_hand():
    """A unit rotation about +z moves the point (1, 0) at (0, 1) and (0, 1) at (-1, 0);
    a translation adds itself. The 3D form with w = (0, 0, 1) agrees in the plane, and
    w = (1, 0, 0) moves (0, 1, 0) at (0, 0, 1)."""
    r2 = np.array([[1.0, 0.0], [0.0, 1.0]])
    np.testing.assert_allclose(dims.rigid_velocity([0.5, 0.0, 1.0], r2, 2), [[0.5, 1.0], [-0.5, 0.0]])
    r3 = np.column_stack([r2, np.zeros(2)])
    np.testing.assert_allclose(dims.rigid_velocity([0.5, 0, 0, 0, 0, 1.0], r3, 3), [[0.5, 1.0, 0], [-0.5, 0.0, 0]])
    np.testing.assert_allclose(dims.rigid_velocity([0, 0, 0, 1.0, 0, 0], [0, 1.0, 0], 3), [0, 0, 1.0])
    np.testing.assert_allclose(dims.rigid_velocity([0, 0, 2.0], [0, 1.0], 2), [-2.0, 0.0])
