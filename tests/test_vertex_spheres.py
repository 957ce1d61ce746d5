"""dem_validation/vertex_spheres.py: every vertex sphere of the YADE vertex model lies inside its
block, at least r from every face plane (the sphere's centre c = v + r d, distance of c to the
plane n . x = o is o - n . c)."""
import numpy as np
import pytest

from dem_validation.vertex_spheres import inset_directions
from limit.geom.geometry import polyhedron


def _clearance(vertices, d, r):
    P = polyhedron(vertices, check_interior=False)
    c = np.asarray(vertices) + r * d
    return (P.face_offsets[None, :] - c @ P.face_normals.T).min()


def test_unit_cube_spheres_sit_r_inside_every_face():
    V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    d = inset_directions(V, [0, 0, 1], 0.01)
    assert _clearance(V, d, 0.01) >= 0.01 * (1 - 1e-9)


def test_a_short_edge_near_a_vertex_still_gets_spheres_inside():
    """A 1 m cube whose top edge at x = 1, y = 1 is cut off by a chamfer 0.2 mm wide: the chamfer's
    plane passes 0.1 mm from the top corners next to it, inside the reach of a sphere of 5 mm
    placed against the three planes through such a corner. The sphere keeps clear of the
    chamfer too (found by the least-squares placement alone, it crossed it)."""
    c = 2e-4
    V = [[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1) if not (x == 1 and y == 1)]
    V += [[1 - c, 1, z] for z in (0, 1)] + [[1, 1 - c, z] for z in (0, 1)]
    V = np.array(V, dtype=float)
    r = 0.005
    d = inset_directions(V, [0, 0, 1], r)
    assert _clearance(V, d, r) >= r * (1 - 1e-9)


def test_a_block_too_thin_for_its_spheres_is_named():
    V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 0.004)], dtype=float)
    with pytest.raises(ValueError, match="sphere"):
        inset_directions(V, [0, 0, 1], 0.005)
