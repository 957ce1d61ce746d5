"""Step 2 on 3D domes: the start from the coarser friction polygon (limit.step2._coarse_plan,
limit.solve.nlp_starts.coarse_slide_faces / transfer).

With the default 24 inscribed sliding faces, every successive-LP run on the dome of 3 rings of
12 voussoirs and a cap ends at a point that is not complementary; with the 8 inscribed faces
(their polygon lies inside the 24-face one) a run verifies 0.479957, and those interface
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
    scene = _dome(meridians=12, rings=3)
    P = assemble(scene)
    lp, _, _ = solve_lp(P)
    N = build(P)
    backend = "highs" if N.n <= 3000 else "clarabel"  # as step2.run picks it
    runs = []
    plan = step2._coarse_plan(P, N, "sla", backend, 0, ("penalty", "random", "friction"), None, runs)
    assert runs[0]["verified"] and runs[0]["alpha"] == pytest.approx(0.479957, abs=1e-5)
    assert plan
    best = None
    for _, z0, _, rho0, _ in plan:
        z, _ = nlp.solve_sla(N, z0, backend, rho0=rho0)
        zf, ok, _, _, _ = nlp.finish(N, z, lp.alpha, backend)
        if ok:
            best = zf[N.ia] if best is None else min(best, zf[N.ia])
    assert best is not None and best <= 0.479957 + 1e-5
