"""Step 2 (the frictional NLP) against closed forms, the global MILP and the iterative LP."""
import numpy as np
import pytest

from limit import step2
from limit.solve import iterative_lp, milp, nlp, nlp_starts
from limit.analysis import analyse, solve_lp
from limit.model.assemble import assemble
from limit.solve.nlp_problem import build
from limit.model.scene import load_scene
from limit.model.yield_domain import TWIST
from limit.solve.outcome import RouteOutcome
from scenes import builders as B


def setup(d):
    P = assemble(load_scene(d))
    sol, _, _ = solve_lp(P)
    assert sol.status == "optimal"
    return P, sol


@pytest.mark.parametrize("dim", [2, 3])
def test_single_block_sliding_nlp_equals_lp_equals_mu(dim):
    mu = 0.35
    res = analyse(load_scene(B.single_block(dim=dim, b=1.0, h=0.5, t=1.0, mu=mu)), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(mu, rel=1e-6)
    assert res["nlp"]["status"] == "optimal"
    assert res["nlp"]["alpha"] == pytest.approx(mu, rel=1e-6)


@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.slow)])  # 3D: about 2.5 s
def test_rocking_and_sliding_combined(dim):
    """NLP < LP; the same value from the closed form, the global MILP and the iterative LP (to 1e-4)."""
    d = B.side_by_side(dim=dim, mu=0.5)
    P, sol = setup(d)
    closed = B.side_by_side_alpha(mu=0.5)
    res = step2.step2(P, sol, method="nlp", global_check=True, iterative=True)
    assert res["status"] == "optimal"
    a = res["alpha"]
    assert sol.alpha == pytest.approx(7 / 17, rel=1e-6)  # associative: B dilates as it slides
    assert a < sol.alpha - 1e-3
    assert a == pytest.approx(closed, rel=1e-4)
    assert res["global"]["status"] == "optimal"
    assert res["global"]["alpha"] == pytest.approx(a, rel=1e-4)
    assert res["iterative_lp"]["status"] == "converged"
    assert res["iterative_lp"]["alpha"] == pytest.approx(a, rel=1e-4)


@pytest.mark.slow  # about 9 s: step 2 and the MILP on the 3 x 3 wall
def test_wall_that_opens_while_it_slides():
    """3 x 3 running-bond wall, mu = 1.2: the LP's dilatant mechanism gives 1.0; the end blocks can
    instead rock about a toe while the joints above open and slide (DEM probe: 0.357)."""
    P, sol = setup(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2))
    res = step2.step2(P, sol, method="nlp", global_check=True)
    assert sol.alpha == pytest.approx(1.0, rel=1e-6)
    assert res["status"] == "optimal"
    assert res["global"]["status"] == "optimal"
    assert res["alpha"] == pytest.approx(res["global"]["alpha"], rel=1e-4)
    assert res["alpha"] == pytest.approx(5 / 14, rel=1e-4)


def test_skip_rule_pure_rocking():
    P, sol = setup(B.portal(dim=2, mu=0.9))
    res = step2.step2(P, sol, method="auto", global_check=True)
    assert res["status"] == "skipped"
    assert "no interface slides or twists" in res["reason"]
    assert res["alpha"] == pytest.approx(sol.alpha)
    # the rule is right here: the global frictional minimum is the LP value
    assert res["global"]["alpha"] == pytest.approx(sol.alpha, rel=1e-6)
    # and the LP's point was checked as a frictional collapse state before the skip
    from limit.solve import verify
    assert res["verification"]["complementarity"] <= verify.TOL_COMP


def test_skip_rule_runs_nlp_when_the_lp_point_fails_the_frictional_check(monkeypatch):
    """No sliding in the LP mechanism is not enough: the LP's point must also pass nlp.check as a
    frictional collapse state, else step 2 runs (here the check is forced to fail on the LP's
    point only, so the portal's step 2 runs and finds the same rocking alpha, 0.2)."""
    from limit.solve import nlp

    P, sol = setup(B.portal(dim=2, mu=0.9))
    real = nlp.check
    calls = []

    def failing_first(N, z, alpha_lp):
        calls.append(1)
        if len(calls) == 1:
            return False, {}, "forced failure"
        return real(N, z, alpha_lp)
    monkeypatch.setattr(nlp, "check", failing_first)
    res = step2.step2(P, sol, method="auto")
    assert len(calls) > 1 and res["status"] == "optimal"
    assert res["alpha"] == pytest.approx(sol.alpha, rel=1e-6)


def _step2_routes_fail(monkeypatch):
    """Stand-ins for both local routes of step 2 (successive and iterative LP): no verified point."""
    def fail(*a, **k):
        return RouteOutcome(False, reason="stand-in: no verified point")
    monkeypatch.setattr(step2, "run", fail)
    monkeypatch.setattr(step2, "_large", fail)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_checked_milp_point_below_step2_becomes_the_answer(monkeypatch, dim):
    """With --global, a MILP point below step 2's alpha that passes the same check is the answer
    (route "global-milp", step 2's own alpha kept in alpha_step2). Step 2's routes are made to
    fail here, so any point is below; the answer must be the closed form of the two blocks side
    by side (scenes.builders.side_by_side_alpha, derived there), checked by nlp.check."""
    from limit.solve import verify

    P, sol = setup(B.side_by_side(dim=dim, mu=0.5))
    _step2_routes_fail(monkeypatch)
    res = step2.step2(P, sol, method="nlp", global_check=True)
    assert res["global"]["status"] == "optimal" and res["global"]["adopted"] is True
    assert res["status"] == "optimal" and res["route"] == "global-milp" and res["alpha_step2"] is None
    assert res["alpha"] == pytest.approx(B.side_by_side_alpha(mu=0.5), rel=1e-6)
    assert res["verification"]["complementarity"] <= verify.TOL_COMP
    assert set(res["mechanism"]) and res["counts"]["slide"] >= 1 and "alpha_rejected" not in res


def test_a_milp_point_that_fails_the_check_is_never_the_answer(monkeypatch):
    """The same, with the check of the MILP's point forced to fail: step 2 stays "failed" with no
    alpha, and the global entry says the point was not adopted and why."""
    P, sol = setup(B.side_by_side(dim=2, mu=0.5))
    _step2_routes_fail(monkeypatch)

    def finish_fails(N, z, alpha_lp, backend, **k):
        return z, False, {}, "forced failure", "unpolished"
    monkeypatch.setattr(nlp, "finish", finish_fails)
    res = step2.step2(P, sol, method="nlp", global_check=True)
    assert res["global"]["alpha"] == pytest.approx(B.side_by_side_alpha(mu=0.5), rel=1e-6)
    assert res["global"]["adopted"] is False and "forced failure" in res["global"]["reason"]
    assert res["status"] == "failed" and res["alpha"] is None and res.get("route") != "global-milp"


def test_skip_rule_runs_nlp_when_lp_mechanism_slides():
    P, sol = setup(B.side_by_side(dim=2, mu=0.5))
    res = step2.step2(P, sol, method="auto")
    assert res["status"] == "optimal"


def test_no_twisting_unknowns_in_2d():
    P, _ = setup(B.side_by_side(dim=2))
    assert not np.any(P.model.kind == TWIST)
    assert P.model.n_x == 3 * len(P.I)
    P3, _ = setup(B.side_by_side(dim=3))
    assert np.any(P3.model.kind == TWIST)


def test_check_rejects_a_corrupted_solution():
    P, sol = setup(B.side_by_side(dim=2, mu=0.5))
    out = step2.run(P, sol)
    N, z = out.N, out.z
    ok, _, _ = nlp.check(N, z, sol.alpha)
    assert ok
    bad = z.copy()
    bad[N.ia] *= 0.9  # a lower alpha with the same stresses breaks equilibrium
    ok, res, why = nlp.check(N, bad, sol.alpha)
    assert not ok and "equilibrium" in why
    bad = z.copy()
    bad[N.sl] += 0.5 * np.abs(bad[N.sl]).max()  # flow on faces that hold: compatibility and complementarity
    ok, res, why = nlp.check(N, bad, sol.alpha)
    assert not ok and "compatibility" in why and "complementarity" in why
    bad = z.copy()
    bad[N.sx] *= 3.0  # stresses beyond the yield domain and out of equilibrium
    ok, res, why = nlp.check(N, bad, sol.alpha)
    assert not ok and ("yield" in why or "equilibrium" in why)


def test_failed_check_gives_failed_status(monkeypatch):
    P, sol = setup(B.side_by_side(dim=2, mu=0.5))
    real = nlp.check

    def corrupt(N, z, alpha_lp):
        z = z.copy()
        z[N.ia] *= 0.5
        return real(N, z, alpha_lp)

    monkeypatch.setattr(nlp, "check", corrupt)
    res = step2.step2(P, sol, method="nlp")
    assert res["status"] == "failed"
    assert res["alpha"] is None
    assert "equilibrium" in res["reason"]


@pytest.mark.slow  # about 90 s: four plain SQP runs from arbitrary starts and the MILP
def test_lp_start_beats_arbitrary_start():
    """The paper's Fig. 4 lesson: plain SQP from an arbitrary start ends at poor points or fails;
    from the LP start it reaches the global minimum (checked by the MILP)."""
    P, sol = setup(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2))
    best = step2.run(P, sol)
    g = milp.global_minimum(P, best.alpha)
    assert g.status == "optimal"
    assert best.ok and best.alpha == pytest.approx(g.alpha, rel=1e-6)
    outcomes = []
    for seed in range(4):
        arb = step2.run(P, sol, solver="slsqp", start="arbitrary", seed=seed, restarts=False)
        outcomes.append(arb.alpha if arb.ok else None)
    # every arbitrary start fails its check or ends more than 10 % above the global minimum
    assert all(a is None or a > 1.1 * g.alpha for a in outcomes), outcomes


def test_nlp_never_above_lp_and_problem_shapes():
    P, sol = setup(B.running_bond_wall(4, 4, dim=2, L=0.4, H=0.3, mu=0.9))
    out = step2.run(P, sol)
    N = build(P)
    assert N.n == 1 + P.model.n_x + P.n_dof + P.model.n_faces
    assert out.ok
    assert out.alpha <= sol.alpha + 1e-9


def test_iterative_lp_on_pure_sliding_block():
    P, sol = setup(B.single_block(dim=2, b=1.0, h=0.5, mu=0.3))
    it = iterative_lp.solve(P, sol)
    assert it.status == "converged"
    assert it.alpha == pytest.approx(0.3, rel=1e-6)


@pytest.mark.slow  # about 15 s: step 2 and the iterative LP on the 30-block 3D wall
def test_3d_wall_nlp_starts_from_an_interior_point_lp_answer():
    """The 6 x 5 running-bond 3D wall (mu = 0.65): the LP answer (Clarabel, interior point) meets
    equilibrium only to its tolerance; phase 1 once re-imposed it on the fixed stresses and HiGHS
    failed ("Solve error"). The wall slides on its base course, alpha = mu, and the iterative LP
    of Gilbert et al. agrees."""
    P, sol = setup(B.running_bond_wall(6, 5, dim=3, mu=0.65))
    res = step2.step2(P, sol, method="nlp", iterative=True)
    assert res["status"] == "optimal", res.get("reason")
    assert res["alpha"] == pytest.approx(0.65, rel=1e-6)
    assert res["iterative_lp"]["alpha"] == pytest.approx(res["alpha"], rel=1e-4)


@pytest.mark.slow  # about 10 s: the full restart plan besides the budgeted run
def test_time_budget_stops_restarts_but_keeps_a_verified_answer():
    """With a budget already spent, no restart begins once the first run is verified: the answer
    is that run's (verified, never above the LP), and the full plan can only do better (here it
    reaches 5/14, the MILP's global minimum in test_wall_that_opens_while_it_slides)."""
    P, sol = setup(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2))
    out = step2.run(P, sol, time_budget=1e-9)
    assert out.ok and out.alpha <= sol.alpha * (1 + 1e-9)
    done = [r for r in out.runs if not r.get("not_run")]
    skipped = [r for r in out.runs if r.get("not_run")]
    assert len(done) == 1 and len(skipped) == 1 and "time budget" in skipped[0]["reason"]
    full = step2.run(P, sol, time_budget=None)
    assert len(full.runs) == len(done) + skipped[0]["not_run"]
    assert full.alpha == pytest.approx(5 / 14, rel=1e-4)
    assert full.alpha <= out.alpha + 1e-9


def test_sla_direction_cost_never_negative_on_a_multiplier():
    """A slack a rounding error below zero must not give its face's multiplier a negative cost
    in the SLA's direction LP (with a mechanism of zero live-load work along it, that LP is
    unbounded: seen on 300-block walls). The clipped gradient equals the exact one elsewhere."""
    P, sol = setup(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2))
    N = build(P)
    z = nlp_starts.lp_start(N, sol)
    s = N.slack(z)
    j = int(np.argmin(s))
    # push face j's slack just below zero along its own row
    row = P.Yh[j].toarray().ravel()
    z[N.sx] += (s[j] + 1e-12) * row / (row @ row)
    assert N.slack(z)[j] < 0
    z[N.sl] = np.abs(z[N.sl]) + 0.1
    exact, clipped = N.comp_grad(z), N.comp_grad(z, clip=True)
    assert exact[N.sl][j] < 0 <= clipped[N.sl].min()
    ok = N.slack(z) >= 0
    np.testing.assert_array_equal(clipped[N.sl][ok], exact[N.sl][ok])
    np.testing.assert_allclose(clipped[N.sx], exact[N.sx])


def cold_bounds(N, P, alpha_ub):
    """The MILP's per-face bounds by a second method: every LP solved on its own by
    scipy.optimize.linprog (lpsub.solve), with no basis carried from one to the next."""
    import scipy.sparse as sp
    from limit.solve import lpsub

    nf, ndof = P.model.n_faces, P.n_dof
    lo, hi = N.bounds()
    lo[N.ia], hi[N.ia] = 0.0, alpha_ub
    S, L = np.full(nf, np.inf), np.full(nf, np.inf)
    for j in range(nf):
        r = lpsub.solve(N.Yx[j].toarray().ravel(), N.Aeq[:ndof], N.beq[:ndof], N.Yx, N.kh, lo, hi)
        if r.ok:
            S[j] = max(N.kh[j] - r.fun, 0.0)
    work = sp.hstack([sp.csr_matrix((1, 1 + P.model.n_x)), sp.csr_matrix(-P.f0h.reshape(1, -1)),
                      sp.csr_matrix((1, nf))]).tocsr()
    for j in range(nf):
        c = np.zeros(N.n)
        c[N.sl.start + j] = -1.0
        r = lpsub.solve(c, N.Aeq[ndof:], N.beq[ndof:], work, np.array([alpha_ub]), lo, hi)
        if r.ok:
            L[j] = max(-r.fun, 0.0)
    return S, L


@pytest.mark.parametrize("dim", [2, 3])
def test_the_milp_bounds_equal_those_of_independent_lps(dim):
    """milp._bounds solves its per-face LPs in one warm-started HiGHS model per family; each
    optimum value is unique, so it must equal the LP solved on its own (cold_bounds), face by
    face, finite and infinite alike. The wall's faces include unbounded multipliers (joints free
    to slide at zero normal force)."""
    P, sol = setup(B.running_bond_wall(3, 3, dim=dim, L=0.4, H=0.4, mu=0.6))
    N = build(P)
    ub = sol.alpha * (1 + 1e-9)
    S, L = milp._bounds(N, P, ub, deadline=float("inf"))
    S0, L0 = cold_bounds(N, P, ub)
    for got, ref in ((S, S0), (L, L0)):
        assert np.array_equal(np.isfinite(got), np.isfinite(ref))
        f = np.isfinite(ref)
        assert f.sum() > 0
        np.testing.assert_allclose(got[f], ref[f], rtol=1e-7, atol=1e-9)


def test_the_global_milp_reports_its_progress(monkeypatch, caplog):
    """A long global check tells where it is: the bound LPs as they go, the branch and cut as it
    starts, and its end with the alpha found (the squat block of the test above: pure sliding at
    alpha = mu = 0.3, since a block b = 1.0 wide and h = 0.5 high overturns only at b / h = 2)."""
    import logging
    monkeypatch.setattr(milp, "PROGRESS_EVERY_S", 0.0)
    P, sol = setup(B.single_block(dim=2, b=1.0, h=0.5, mu=0.3))
    with caplog.at_level(logging.INFO, logger="limit.solve.milp"):
        g = milp.global_minimum(P, sol.alpha)
    lines = [r.getMessage() for r in caplog.records if r.name == "limit.solve.milp"]
    nf = P.model.n_faces
    assert lines[0] == f"global MILP: bounds of {nf} yield faces' slacks and multipliers, {2 * nf} LPs"
    assert any(f"of {2 * nf} LPs" in t and t.startswith("global MILP: bounds, ") for t in lines)
    assert any(t.startswith(f"global MILP: branch and cut on {nf} binaries") for t in lines)
    assert g.status == "optimal" and g.alpha == pytest.approx(0.3, rel=1e-6)
    assert lines[-1].startswith("global MILP: optimal") and "alpha 0.3" in lines[-1]


def test_a_failed_step_2_reports_the_run_nearest_to_a_collapse_state(monkeypatch):
    """Where no run verifies, the part reports the run whose point is nearest to complementary
    (its residuals, reason and ``alpha_rejected``), not the one with the lowest alpha: a run cut
    short by the budget can end near alpha 0 with a residual of 0.5 (the imported dome's step 2
    reported exactly that, where its best successive-LP run had reached 3.6e-4). Here every
    run's point fails the check with a stand-in residual; the first has the lowest residual and
    the highest alpha."""
    P, sol = setup(B.single_block(dim=2, b=1.0, h=0.5, t=1.0, mu=0.35))
    seen = []

    def stand_in(N, z, alpha_lp, backend, *a, **k):
        seen.append(1)
        zc = z.copy()
        zc[N.ia], comp = (0.3, 1e-3) if len(seen) == 1 else (1e-9, 0.5)
        return zc, False, {"complementarity": comp}, f"complementarity residual {comp:.2e} > 1e-06", "unpolished"

    monkeypatch.setattr(nlp, "finish", stand_in)
    monkeypatch.setattr(nlp, "needs_nlp", lambda P, sol: (True, "stand-in"))
    from limit.model.assemble import Options

    P = assemble(P.scene, Options(settings={"also_iterative": False}))
    res = step2.step2(P, sol, method="nlp", time_budget=30.0)
    assert len(seen) > 2 and res["status"] == "failed"
    assert res["verification"]["complementarity"] == 1e-3 and res["alpha_rejected"] == pytest.approx(0.3)
    assert "1.00e-03" in res["reason"]
