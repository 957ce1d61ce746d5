"""Step 2 on 3D domes: the start from the coarser friction polygon (limit.step2._coarse_plan,
limit.solve.nlp_starts.coarse_slide_faces / transfer).

With the default 24 inscribed sliding faces, every successive-LP run on the dome of 3 rings of
12 voussoirs and a cap ends at a point that is not complementary; with the 8 inscribed faces
(their polygon lies inside the 24-face one) a run verifies, and those interface
actions, with the mechanism re-solved for the 24 faces, are a frictional collapse state of the
24-face model.
"""
import pytest

from limit import step2
from limit.analysis import solve_lp
from limit.model.assemble import Options, assemble
from limit.model.scene import load_scene
from limit.solve import nlp, nlp_starts
from limit.solve.nlp_problem import build
from scenes import generators as G


def _dome(**kw):
    return load_scene(G.dome(**kw))


@pytest.mark.parametrize("n,fit,expect", [(24, "auto", 8), (12, "auto", 4), (8, "auto", None), (4, "auto", None),
                                          (16, "auto", None), (24, "circumscribed", None), (36, "auto", 12)])
def test_coarse_slide_faces(n, fit, expect):
    P = assemble(_dome(meridians=4, rings=1), Options(n_slide=n, slide_fit=fit))
    assert nlp_starts.coarse_slide_faces(P) == expect


def test_coarse_polygon_lies_inside():
    """Every stress admissible with the coarse faces is admissible with the fine ones: each
    coarse face is a non-negative combination of fine faces' rows (checked on the polygon's
    vertices: the coarse vertices are fine vertices)."""
    import numpy as np
    from limit.model.yield_domain import _slide_dirs

    for n, nc in ((24, 8), (12, 4), (36, 12)):
        d, c = _slide_dirs(n, "inscribed")
        dc, cc = _slide_dirs(nc, "inscribed")
        th = 2 * np.pi * (np.arange(nc) + 0.5) / nc  # coarse vertices, on the friction circle
        v = np.column_stack([np.cos(th), np.sin(th)])
        assert (v @ d.T).max() <= c + 1e-12  # inside every fine face


@pytest.mark.slow  # step 2 of a 37-block dome with 8 faces, then SLA runs with 24
def test_dome_3x12_verifies_from_the_coarse_polygon():
    """The coarse model's step 2 verifies (within its own plan, from the LP's point or its
    simplex vertex), and the SLA from its point, transferred to the 24 faces, verifies at or below
    it. Why at or below: the transferred actions are admissible for the 24 faces (the 8-face
    polygon lies inside, test_coarse_polygon_lies_inside) and balance the loads at the coarse
    alpha, so that alpha is attained by a statically admissible state of the fine model, which the
    SLA starts from and does not leave upwards. Verified means the independent check
    (nlp.check: equilibrium, yield, flow rule and complementarity residuals) passes; the
    successive LP's path to a local solution differs between machines in the last digits of the
    LP solutions, so no one local alpha is asserted, only the bounds that hold for every one:
    0 < alpha <= the LP's (the associative upper bound)."""
    scene = _dome(meridians=12, rings=3)
    P = assemble(scene)
    lp, _, _ = solve_lp(P)
    N = build(P)
    backend = "highs" if N.n <= 3000 else "clarabel"  # as step2.run picks it
    runs = []
    plan = step2._coarse_plan(P, N, "sla", backend, 0, ("penalty", "random", "friction", "vertex"), None, runs)
    coarse = runs[0]
    assert coarse["verified"], coarse["reason"]
    assert 0 < coarse["alpha"] <= lp.alpha
    assert plan
    best = None
    for _, z0, _, rho0, _ in plan:
        z, _ = nlp.solve_sla(N, z0, backend, rho0=rho0)
        zf, ok, _, _, _ = nlp.finish(N, z, lp.alpha, backend)
        if ok:
            best = zf[N.ia] if best is None else min(best, zf[N.ia])
    assert best is not None and 0 < best <= coarse["alpha"] + 1e-5


def test_vertex_start_only_where_the_lp_ended_inside_its_optimal_face():
    """The vertex start is HiGHS's basic solution: none where the LP's own solver is the
    simplex; from Clarabel's interior point, a start at the same alpha (the LP optimum is unique
    in alpha, its point is not) whose flow rule holds (phase 1)."""
    P = assemble(_dome(meridians=4, rings=1))
    N = build(P)
    lp_ip, _, _ = solve_lp(P, solver="clarabel")
    lp_vx, _, _ = solve_lp(P, solver="highs")
    assert nlp_starts.vertex_start(P, N, lp_vx, "highs") is None
    z0 = nlp_starts.vertex_start(P, N, lp_ip, "highs")
    assert z0 is not None
    assert z0[N.ia] == pytest.approx(lp_ip.alpha, rel=1e-6)

