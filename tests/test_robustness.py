"""Solvers that can be confidently wrong, and the checks that notice.

The 27-voussoir semicircular arch (t/R = 0.15) under a horizontal body force
collapses by hinging at alpha = 0.14534 for every mu from 0.6 up: the
reference is the four-hinge mechanism search of scenes/closed_forms.py
(independent of limit/; Gilbert et al. 2006 report the same arch). Unscaled,
HiGHS's dual simplex was seen to report "optimal" with 0.0895 at mu = 10; here
the default solvers must give the hinging value, and every other selectable
one the hinging value or a failure status.
"""
import json

import numpy as np
import pytest

from limit.solve import lp as lpmod, verify
from limit.analysis import solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from scenes import builders as B
from scenes.catalog import CATALOG_DIR

#: the solvers the package picks by itself: these must answer, never fail, on this arch
DEFAULT_SOLVERS = ("auto", "clarabel", "ipm")


@pytest.fixture(scope="module")
def arch_reference():
    """The four-hinge alpha of the arch, independent of limit/: the value that
    scenes.catalog stored in arch-semicircular-27-2d.json (``expected``, from
    ``arch_reference(27, 1.0, 0.15)`` rounded to 10 digits). Recomputing it takes about 50 s;
    tests/test_catalog.py::test_stored_four_hinge_references_are_the_searches (its 27-voussoir
    case marked slow) checks this value against the four-hinge search."""
    path = CATALOG_DIR / "arch-semicircular-27-2d.json"
    alpha = json.loads(path.read_text())["expected"]["alpha"]
    assert alpha == pytest.approx(0.14534, abs=5e-6)
    return alpha


@pytest.mark.parametrize("mu", [0.6, 10.0, 100.0])
@pytest.mark.parametrize("solver", list(lpmod.SOLVERS))
def test_arch_same_alpha_every_solver(mu, solver, arch_reference):
    P = assemble(load_scene(B.arch(27, R=1.0, t=0.15, dim=2, mu=mu)))
    sol, attempts, _ = solve_lp(P, solver, fallback=False)
    assert sol.status in (("optimal",) if solver in DEFAULT_SOLVERS else ("optimal", "failed")), sol.reason
    if sol.status == "optimal":
        assert sol.alpha == pytest.approx(arch_reference, rel=1e-6)
    else:
        assert sol.alpha is None and sol.reason


def test_wrong_optimal_answer_is_caught_and_resolved(monkeypatch, arch_reference):
    """A solver that reports "optimal" with a wrong alpha: the check rejects it and the next solver answers."""
    P = assemble(load_scene(B.arch(27, R=1.0, t=0.15, dim=2, mu=10.0)))
    real = lpmod.static_lp

    def liar(P, solver, overrides=None):
        sol = real(P, solver, overrides)
        if solver == "highs":
            sol.alpha = 0.0895  # what unscaled HiGHS reported for this arch at mu = 10
        return sol

    monkeypatch.setattr(lpmod, "static_lp", liar)
    sol, attempts, _ = solve_lp(P, "highs", fallback=True)
    assert attempts[0]["solver"] == "highs" and not attempts[0]["verified"]
    assert "equilibrium" in attempts[0]["reason"]
    assert sol.status == "optimal" and sol.solver != "highs"
    assert sol.alpha == pytest.approx(arch_reference, rel=1e-6)


def test_wrong_answer_without_fallback_is_failed(monkeypatch):
    P = assemble(load_scene(B.single_block(dim=2)))
    real = lpmod.static_lp

    def liar(P, solver, overrides=None):
        sol = real(P, solver, overrides)
        sol.u = sol.u * 1.5  # a mechanism that does not do unit work: normalisation and gap break
        return sol

    monkeypatch.setattr(lpmod, "static_lp", liar)
    sol, attempts, _ = solve_lp(P, "clarabel", fallback=False)
    assert sol.status == "failed" and sol.alpha is None
    assert "normalisation" in sol.reason


def test_inaccurate_status_never_optimal(monkeypatch):
    P = assemble(load_scene(B.single_block(dim=2)))
    real = lpmod._solve

    def inaccurate(prob, solver, overrides=None):
        status, t = real(prob, solver, overrides)
        return "optimal_inaccurate", t

    monkeypatch.setattr(lpmod, "_solve", inaccurate)
    sol = lpmod.static_lp(P, "clarabel")
    assert sol.status == "inaccurate"
    # a verified inaccurate answer is accepted only after the independent check passes
    full, attempts, _ = solve_lp(P, "clarabel", fallback=False)
    assert attempts[0]["status"] == "optimal_inaccurate"
    assert full.status == ("optimal" if attempts[0]["verified"] else "failed")


def test_scaled_problem_conditioning_is_independent_of_units_and_mu():
    """Nondimensionalisation: the scaled matrices do not change with the units or with mu."""
    d = B.arch(27, R=1.0, t=0.15, dim=2, mu=0.6)
    from scenes.transform import transform

    P1 = assemble(load_scene(d))
    P2 = assemble(load_scene(transform(d, s=1000.0)))
    d100 = dict(d, friction=100.0)
    P3 = assemble(load_scene(d100))
    assert np.allclose(P1.Eh.toarray(), P2.Eh.toarray(), rtol=1e-9, atol=1e-12)
    for P in (P1, P2, P3):
        assert abs(P.Yh).max() == pytest.approx(1.0)
        assert abs(P.Eh).max() <= 1.0 + 1e-12
    assert verify.TOL_EQ <= 1e-6


def test_block_touching_nothing_is_named():
    """A block lifted clear of the one below (a modelling slip): infeasible, with the block named, no solver run."""
    d = B.stack(2, dim=2)
    d["blocks"][-1]["box"]["center"][1] += 0.2
    P = assemble(load_scene(d))
    sol, attempts, _ = solve_lp(P, "auto")
    assert sol.status == "infeasible" and sol.alpha is None
    assert "s1" in sol.reason and "touch no other block" in sol.reason
    assert attempts == []
    # the same stack in contact is untouched by the check
    sol, _, _ = solve_lp(assemble(load_scene(B.stack(2, dim=2))), "auto")
    assert sol.status == "optimal"
