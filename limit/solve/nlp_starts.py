"""Step 2's starting points: the restart policy of the successive LP (:mod:`limit.solve.nlp`).

A start is a point z of :class:`limit.solve.nlp_problem.NLPProblem` (alpha, scaled interface
actions, block velocities, plastic multipliers), made compatible with the non-associative
flow by :func:`limit.solve.nlp.phase1` before the solvers take it: the associative LP's
answer (:func:`lp_start`), seeded random points (:func:`arbitrary_start`,
:data:`RANDOM_RESTARTS`), and the associative LP at reduced friction
(:func:`reduced_friction_starts`).
"""
from __future__ import annotations

import numpy as np

from limit.solve.status import Status
from limit.solve.nlp import phase1
from limit.solve.nlp_problem import NLPProblem


def lp_start(N: NLPProblem, lp_sol) -> np.ndarray:
    """The LP solution as a point of the NLP (flow generally violated)."""
    return N.scale(lp_sol.alpha, lp_sol.x, lp_sol.u, lp_sol.lam)


def arbitrary_start(N: NLPProblem, seed: int = 0) -> np.ndarray:
    """A start that knows nothing of the LP: small random stresses and multipliers, alpha = 0.5."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(0.0, 1.0, N.n)
    z[N.ia] = 0.5
    return z


#: randomised SLA restarts from the LP start (by problem size: unknowns <= 5000, above)
RANDOM_RESTARTS = (6, 2)
#: friction factors of the extra associative-LP starts (see :func:`reduced_friction_starts`)
FRICTION_FACTORS = (0.5, 0.25)


def reduced_friction_lp(P, factor: float):
    """The associative LP of P with every friction coefficient and cohesion times ``factor`` (its
    solution, or None when it has no optimum)."""
    import dataclasses

    from limit.solve.checked_lp import solve_lp
    from limit.model.assemble import assemble

    P2 = assemble(P.scene, P.options, interfaces=dataclasses.replace(P.I, mu=P.I.mu * factor,
                                                                       cohesion=P.I.cohesion * factor))
    sol2, _, _ = solve_lp(P2)
    return sol2 if sol2.status == Status.OPTIMAL else None


def reduced_friction_starts(P, N: NLPProblem, backend: str, factors=FRICTION_FACTORS) -> list:
    """Starts from the associative LP solved with the friction coefficients scaled down.

    Its stresses satisfy the real (higher) friction bound, and it collapses through
    mechanisms in which joints slide more freely; made compatible with the
    non-associative flow (phase 1) they lead the NLP to collapses in which joints
    open and slide at zero normal force, which the dilatant mechanism of the
    full-friction LP cannot reach. Measured on running-bond walls (bench/nlp_bench.py):
    without these starts the NLP missed the global minimum in half of the cases.
    """
    out = []
    for f in factors:
        sol2 = reduced_friction_lp(P, f)
        if sol2 is None:
            continue
        z = N.join(sol2.alpha, sol2.x / P.Dx, np.zeros(P.n_dof), np.zeros(P.model.n_faces))
        z0, _ = phase1(N, z, backend)
        if z0 is not None:
            out.append((f"lp-mu*{f:g}", z0))
    return out


#: the LP solvers whose optimum is a vertex (a basic solution); the others end inside the optimal face
VERTEX_SOLVERS = ("highs",)


def vertex_start(P, N: NLPProblem, lp_sol, backend: str) -> np.ndarray | None:
    """A second start from the LP's optimal face: the basic solution of HiGHS's dual simplex,
    made compatible with the non-associative flow (phase 1); None where ``lp_sol`` is a vertex
    already (its solver is in :data:`VERTEX_SOLVERS`), or the simplex solution fails its check.

    An interior-point LP (Clarabel, ECOS, the project's IPM) ends near the centre of the optimal
    face, where every joint that can flow carries a share of the mechanism; the simplex ends at
    a vertex, with a mechanism on few joints. The two lead the successive LP to different local
    solutions: on the 8-face model of a dome of 3 rings of 12 voussoirs and a cap, the 12 runs
    from Clarabel's point end at points that are not complementary (residuals 1.8e-3 to 1.4e-2),
    and the first run from the vertex verifies (docs/performance.md).
    """
    from limit.solve.checked_lp import solve_lp

    if lp_sol.solver in VERTEX_SOLVERS:
        return None
    sol, _, _ = solve_lp(P, solver=VERTEX_SOLVERS[0], fallback=False)
    if sol.status != Status.OPTIMAL:
        return None
    z0, _ = phase1(N, lp_start(N, sol), backend)
    return z0


def coarse_slide_faces(P) -> int | None:
    """The sliding faces of the coarser friction polygon of :func:`coarse_polygon_starts`, or None
    where there is none: a 3D scene of the "paper" model whose polygon is inscribed with n faces,
    and the largest even n_c >= 4 with n / n_c odd (> 1). The inscribed n_c-gon's vertices, at
    angles (j + 1/2) 2 pi / n_c, are then vertices of the n-gon: it lies inside it, and a stress
    admissible with n_c faces is admissible with n."""
    from limit.model.assemble import friction_model
    from limit.model.yield_domain import resolve_fit

    if P.scene.dim != 3 or P.model.name != "paper":
        return None
    n, fit = friction_model(P.scene, P.options)
    if resolve_fit(n, fit) != "inscribed":
        return None
    for r in range(3, n // 4 + 1, 2):
        if n % r == 0 and (n // r) % 2 == 0 and n // r >= 4:
            return n // r
    return None


def coarse_model(P, n_coarse: int):
    """P assembled again with ``n_coarse`` inscribed sliding faces (the same interfaces)."""
    import dataclasses

    from limit.model.assemble import assemble

    return assemble(P.scene, dataclasses.replace(P.options, n_slide=n_coarse, slide_fit="inscribed"), interfaces=P.I)


def transfer(N: NLPProblem, N_coarse: NLPProblem, z_coarse: np.ndarray, backend: str) -> np.ndarray | None:
    """A frictional point of the coarse model (:func:`coarse_model`) as a start of N: its alpha and
    interface actions (admissible in N: the coarse polygon lies inside), its mechanism re-solved
    for N's faces by :func:`limit.solve.nlp.phase1` (None where that fails)."""
    a, x, u, _ = N_coarse.unscale(z_coarse)
    z, _ = phase1(N, N.scale(a, x, u, np.zeros(N.P.model.n_faces)), backend)
    return z
