"""Step 2 at scale (limit/solve/step2_large.py): the iterative LP on the structured interior
point method, snapped to an exactly complementary point and checked independently.

Closed forms used (derivations in scenes/builders.py):
  * a block b x h wedged between a fixed floor and a fixed ceiling slides on both at
    alpha = mu^2 h / b when b < mu h (confined_block_alpha); its associative LP is
    unbounded (sliding dilates, the ceiling forbids it);
  * a slender block pushing a squat one: frictional 23/61 at mu = 0.5 (side_by_side_alpha).
The mixed-integer LP (limit/solve/milp.py) is the independent global reference on a small wall.
"""
import dataclasses
import json
import subprocess
import sys

import pytest

from limit import step2
from limit.settings import DEFAULT
from limit.solve import nlp, step2_large
from limit.solve.outcome import RouteOutcome
from limit.analysis import analyse, solve_lp
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from scenes import builders as B


def _solved(data):
    P = assemble(load_scene(data))
    sol, _, _ = solve_lp(P)
    return P, sol


def _set(monkeypatch, P, **changes):
    """P's settings (limit.settings) with ``changes``, for this test only."""
    monkeypatch.setattr(P, "options", dataclasses.replace(P.options, settings=P.options.settings.replace(changes)))


@pytest.mark.parametrize("b,h,mu", [(0.4, 1.0, 0.5), (0.3, 1.2, 0.6)])
def test_confined_block_from_an_unbounded_lp(b, h, mu):
    P, sol = _solved(B.confined_block(2, b=b, h=h, mu=mu))
    assert sol.status == "unbounded"
    out = step2_large.solve(P, sol)
    assert out.ok and out.starts[0]["start"] == "dead-load"
    assert out.alpha == pytest.approx(B.confined_block_alpha(b, h, mu), rel=1e-6)


def test_confined_block_3d_through_analyse():
    res = analyse(load_scene(B.confined_block(3, b=0.4, h=1.0, t=0.5, mu=0.5)), method="auto").data
    assert res["lp"]["status"] == "unbounded"
    assert res["nlp"]["status"] == "optimal" and res["nlp"]["route"] == "iterative-lp"
    assert res["nlp"]["alpha"] == pytest.approx(0.625, rel=1e-6)


@pytest.mark.slow  # about 3 s: limit solve end to end in a subprocess
def test_cli_solve_auto_on_the_catalog_confined_block(tmp_path):
    out = tmp_path / "r.json"
    p = subprocess.run([sys.executable, "-m", "limit", "solve", "scenes/catalog/confined-block-2d.json",
                        "--method", "auto", "--json", str(out)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    r = json.loads(out.read_text())
    assert r["lp"]["status"] == "unbounded" and r["lp"]["alpha"] is None
    assert r["nlp"]["alpha"] == pytest.approx(0.5 ** 2 * 1.0 / 0.4, rel=1e-6)


def test_side_by_side_matches_the_closed_form_and_the_successive_lp():
    data = B.side_by_side(dim=2, mu=0.5)
    P, sol = _solved(data)
    big = step2_large.solve(P, sol)
    sla = step2.step2(P, sol)
    assert big.ok and big.alpha == pytest.approx(23 / 61, rel=1e-6)
    assert sla["alpha"] == pytest.approx(big.alpha, rel=1e-6)


@pytest.mark.slow  # about 4 s: the large route and the MILP on a small wall
def test_small_wall_agrees_with_the_global_minimum():
    """A 3-course running-bond wall of 0.4 x 0.3 m blocks (mu 0.9): the MILP proves the global
    frictional minimum; every verified start of the large route is a collapse state, so
    never below it, and here the best one reaches it."""
    from limit.solve import milp
    P, sol = _solved(B.running_bond_wall(3, 2, dim=2, L=0.4, H=0.3, mu=0.9))
    big = step2_large.solve(P, sol)
    g = milp.global_minimum(P, sol.alpha, time_limit=300)
    assert g.status == "optimal" and big.ok
    assert big.alpha_worst >= g.alpha - 1e-7
    assert big.alpha == pytest.approx(g.alpha, rel=1e-6)


def test_a_failed_check_is_failed_never_a_number(monkeypatch):
    P, sol = _solved(B.confined_block(2))
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    part = step2.step2(P, sol)
    assert part["status"] == "failed" and part["alpha"] is None and part["route"] == "iterative-lp"


def test_a_start_whose_residual_stalls_stops_early(monkeypatch):
    """A start that never reaches a checked point and whose complementarity residual has no
    new low (forced: 1.0 at every LP) halves its relaxation every large_stall LPs down to
    large_omega_min, then stops as stalled after large_stall more, long before large_max_iter; it
    is never a number."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    (label, n0), = step2_large.starts(P, sol, factors=(1.0,))
    r = step2_large.run_start(P, step2_large.build(P), n0, sol.alpha)
    halvings = 0
    om = DEFAULT.large_omega_2d
    while om > DEFAULT.large_omega_min:
        om, halvings = om / 2, halvings + 1
    assert not r["verified"] and r["z"] is None and r["reason"].startswith("stalled")
    assert r["omega"] == DEFAULT.large_omega_min
    assert r["iterations"] == (halvings + 1) * DEFAULT.large_stall + 1 < DEFAULT.large_max_iter


def test_a_very_large_2d_wall_stalls_by_its_own_count(monkeypatch):
    """The same forced stall with the wall counted as very large (very_large_min_free 1, 2D): the
    relaxation halves every large_stall_very_large LPs instead of every large_stall, so the start
    stops after (halvings + 1) x large_stall_very_large + 1 LPs, and its reason names that count."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, very_large_min_free=1, large_stall_very_large=5, large_stall=9)
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    (label, n0), = step2_large.starts(P, sol, factors=(1.0,))
    r = step2_large.run_start(P, step2_large.build(P), n0, sol.alpha)
    om, halvings = DEFAULT.large_omega_2d, 0  # 9 free blocks: not one round, so omega starts here
    while om > DEFAULT.large_omega_min:
        om, halvings = om / 2, halvings + 1
    assert not r["verified"] and r["reason"].startswith("stalled") and "for 5 LPs" in r["reason"]
    assert r["iterations"] == (halvings + 1) * 5 + 1


def test_a_residual_that_stops_falling_is_snapped_from_its_best_iterate(monkeypatch):
    """Forced residuals 0.5, 5e-3, then 6e-3, 7e-3, ... (rising): never below large_snap_comp, so
    only the plateau rule snaps, once (each snap backend asked in turn), large_plateau LPs after
    the low and from the iterate of the low (the second LP); a later plateau at the same low
    is not snapped again."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    seen, snapped = [], []

    def check(N, z, a):
        seen.append(z)
        k = len(seen)
        return False, {"complementarity": 0.5 if k == 1 else 5e-3 + 1e-3 * (k - 2)}, "forced failure"

    def finish(N, z, a, backend, **kw):
        snapped.append((len(seen), z))
        return None, False, None, None, ""

    monkeypatch.setattr(nlp, "check", check)
    monkeypatch.setattr(nlp, "finish", finish)
    (label, n0), = step2_large.starts(P, sol, factors=(1.0,))
    r = step2_large.run_start(P, step2_large.build(P), n0, sol.alpha)
    assert not r["verified"] and r["reason"].startswith("stalled")
    assert {k for k, _ in snapped} == {2 + DEFAULT.large_plateau} and r["snaps"] == 1
    assert all(z is seen[1] for _, z in snapped)


@pytest.mark.parametrize("backend", ["highs", "clarabel", "ipm"])
def test_a_snap_past_its_deadline_fails_and_gives_no_point(backend):
    """The start's deadline reaches into the snap's LPs: past it, each backend is stopped
    (told a time limit of zero or less) and the snap is a failure, never a point."""
    import time

    from limit.solve import lpsub, nlp_starts

    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    N = step2_large.build(P)
    out = step2_large.snap(N, nlp_starts.lp_start(N, sol), "support", backend, deadline=time.perf_counter() - 1.0)
    assert out.z is None and "time limit" in out.note
    assert not out.infeasible and not out.diverged  # a time limit proves nothing about the piece
    if backend == "ipm":  # the statics of limit/solve/piece_statics.py: no LP front end
        return
    res = lpsub.solve([1.0], None, None, None, None, [0.0], [1.0], backend, time_limit=0.0)
    assert not res.ok and res.z is None and not res.no_point


@pytest.mark.slow  # about 2-3.5 s: the large route on walls
def test_large_walls_run_one_round_of_starts(monkeypatch):
    """From one_round_min_free free blocks on only as many starts as workers (the first
    friction factors); below it every factor's start, each listed with its label."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, one_round_min_free=5)
    out = step2_large.solve(P, sol, workers=1)
    assert [r["start"] for r in out.starts] == ["lp"] and out.starts[0]["iterations"] > 0
    _set(monkeypatch, P, one_round_min_free=10 ** 6)
    out = step2_large.solve(P, sol, workers=1)
    assert [r["start"] for r in out.starts] == ["lp", "lp-mu*0.5", "lp-mu*0.25"] and out.ok


@pytest.mark.slow  # about 20 s: the large route twice on a 3D wall
def test_a_3d_wall_whose_lp_stalls_near_its_optimum_still_verifies(monkeypatch):
    """A 4 x 3 running-bond 3D wall (mu 0.7) slides as one on its base: H = mu W, alpha = mu
    (the associative LP gives the same 0.7, an upper bound). Its fourth iterative LP stalls at
    residuals of 1e-8 to 8e-7 short of 1e-9; with the interior point's best iterate taken
    (iterative_lp.ITERATIVE_ALMOST) every start verifies mu, without it every start failed."""
    from limit.solve import iterative_lp

    P, sol = _solved(B.running_bond_wall(4, 3, dim=3, mu=0.7))
    out = step2_large.solve(P, sol, workers=1)
    assert out.ok and out.n_verified == 3 and out.alpha == pytest.approx(0.7, abs=1e-9)
    monkeypatch.setattr(iterative_lp, "ITERATIVE_ALMOST", None)
    _set(monkeypatch, P, large_patience_round_3d=1.0)  # the first round's failure, not a second round's
    out = step2_large.solve(P, sol, workers=1)
    assert not out.ok and "not converged" in out.reason


def _plain_lps_fail(monkeypatch) -> list:
    """Every start of a first round (plain LPs, patience 1) fails at once (forced); a start of a
    second round (proximal LPs, or more patience) runs as usual. Returns the (proximal,
    patience) of each start, as asked."""
    real, asked = step2_large.run_start, []

    def forced(P, N, nstar0, alpha_ref, proximal=None, patience=1.0, **kw):
        asked.append((proximal, patience))
        if not proximal and patience == 1.0:
            return {"verified": False, "alpha": None, "z": None, "how": None, "iterations": 0, "snaps": 0,
                    "time_s": 0.0, "reason": "forced failure"}
        return real(P, N, nstar0, alpha_ref, proximal=proximal, patience=patience, **kw)
    monkeypatch.setattr(step2_large, "run_start", forced)
    return asked


def test_where_no_start_verifies_the_starts_run_again_with_the_proximal_qp(monkeypatch):
    """2D side-by-side blocks (scenes.builders.side_by_side, mu 0.5): the slender block rocks on
    the squat one and pushes it to slide; the builder's work and equilibrium equations give
    alpha = 23/61 (its docstring), below the associative LP's 7/17. With every plain-LP start
    failing (forced), the route runs its starts again, each LP the proximal QP
    (large_proximal_round), and that round verifies 23/61; with the setting off it fails."""
    P, sol = _solved(B.side_by_side(dim=2, mu=0.5))
    asked = _plain_lps_fail(monkeypatch)
    out = step2_large.solve(P, sol, workers=1)
    labels = [r["start"] for r in out.starts]
    assert labels == ["lp", "lp-mu*0.5", "lp-mu*0.25", "lp (proximal)", "lp-mu*0.5 (proximal)", "lp-mu*0.25 (proximal)"]
    assert asked == [(None, 1.0)] * 3 + [(True, 1.0)] * 3
    assert out.ok and out.start.endswith("(proximal)") and out.alpha == pytest.approx(23 / 61, rel=1e-6)
    _set(monkeypatch, P, large_proximal_round=False)
    out = step2_large.solve(P, sol, workers=1)
    assert not out.ok and len(out.starts) == 3 and "forced failure" in out.reason


def test_in_3d_the_second_round_is_a_patient_one(monkeypatch):
    """The same blocks in 3D (the closed form holds for any thickness: every term of it scales
    with t) and the same forced failure: the second round keeps plain LPs and multiplies the
    stall count and the LP cap by large_patience_round_3d, and verifies 23/61; with that
    setting 1 there is no second round."""
    P, sol = _solved(B.side_by_side(dim=3, mu=0.5))
    asked = _plain_lps_fail(monkeypatch)
    out = step2_large.solve(P, sol, workers=1)
    assert [r["start"] for r in out.starts][3:] == ["lp (patient)", "lp-mu*0.5 (patient)", "lp-mu*0.25 (patient)"]
    assert asked == [(None, 1.0)] * 3 + [(None, DEFAULT.large_patience_round_3d)] * 3
    assert out.ok and out.start.endswith("(patient)") and out.alpha == pytest.approx(23 / 61, rel=1e-6)
    _set(monkeypatch, P, large_patience_round_3d=1.0)
    out = step2_large.solve(P, sol, workers=1)
    assert not out.ok and len(out.starts) == 3


def test_a_patient_start_stalls_after_that_many_times_the_lps(monkeypatch):
    """With every check failing (forced, residual 1.0 at every LP), a start halves its relaxation
    every large_stall LPs and stops as stalled large_stall LPs after the last halving: with
    patience 2, (halvings + 1) x 2 large_stall + 1 LPs."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    (label, n0), = step2_large.starts(P, sol, factors=(1.0,))
    r = step2_large.run_start(P, step2_large.build(P), n0, sol.alpha, patience=2.0)
    om, halvings = DEFAULT.large_omega_2d, 0
    while om > DEFAULT.large_omega_min:
        om, halvings = om / 2, halvings + 1
    stall = 2 * DEFAULT.large_stall
    assert r["reason"].startswith("stalled") and f"for {stall} LPs" in r["reason"]
    assert r["iterations"] == (halvings + 1) * stall + 1


def test_the_proximal_round_does_not_run_where_the_lps_are_proximal_already(monkeypatch):
    """The same forced failure on a 2D wall counted from prox_min_free free blocks on (its first
    round is proximal already): no second round."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, prox_min_free=1, large_proximal_round=True)
    asked = _plain_lps_fail(monkeypatch)
    out = step2_large.solve(P, sol, workers=1)
    assert asked == [(None, 1.0)] * 3 and len(out.starts) == 3


def test_large_3d_walls_start_from_the_reduced_friction_lps(monkeypatch):
    """In 3D, from one_round_min_free free blocks on, the one round's starts are the LPs at 0.5 mu
    and 0.25 mu (START_FACTORS_ONE_ROUND_3D: the associative LP's own start measured slowest
    and not lowest there); 2D keeps the LP's own start first."""
    seen = []
    monkeypatch.setattr(step2_large, "_run_parallel", lambda P, lp_sol, plan, *a, **k: seen.append(
        [lab for lab, _ in plan]) or [step2_large._not_run("spied")] * len(plan))
    for dim in (3, 2):
        P, sol = _solved(B.running_bond_wall(3, 3, dim=dim, mu=0.9))
        _set(monkeypatch, P, one_round_min_free=5, large_proximal_round=False, large_patience_round_3d=1.0)
        step2_large.solve(P, sol, workers=2)
    assert seen == [["lp-mu*0.5", "lp-mu*0.25"], ["lp", "lp-mu*0.5"]]


@pytest.mark.slow  # about 2-3.5 s: the large route on a wall
def test_large_scenes_take_the_large_route(monkeypatch):
    """solver='auto' picks the route by size (the setting large_min_free, free blocks)."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, large_min_free=5)
    part = step2.step2(P, sol, method="nlp")
    assert part["route"] == "iterative-lp" and part["n_starts"] == 3 and part["status"] == "optimal"
    assert part["alpha_best"] <= part["alpha_worst"]


@pytest.mark.slow  # about 3 s: the large route's starts twice, in parallel and one after another
def test_starts_in_parallel_give_what_they_give_one_after_another():
    """Both cores: the starts run in two processes; same verified alphas, start by start."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    one = step2_large.solve(P, sol, workers=1)
    two = step2_large.solve(P, sol, workers=2)
    assert one.workers == 1 and two.workers == 2
    assert [r["alpha"] for r in one.starts] == pytest.approx([r["alpha"] for r in two.starts], rel=1e-9)


@pytest.mark.parametrize("dim,warm", [(2, True), (3, False)])
def test_large_walls_warm_start_their_lps_in_2d_only(monkeypatch, dim, warm):
    """From one_round_min_free free blocks on (lowered here to 1), each LP of a 2D start begins
    at the last LP's point; in 3D it does not (measured worse there, WARM_START_DIMS)."""
    from limit.solve import iterative_lp

    seen = []
    orig = iterative_lp.solve

    def spy(*a, **kw):
        seen.append(kw.get("warm_start"))
        return orig(*a, **kw)

    monkeypatch.setattr(iterative_lp, "solve", spy)
    P, sol = _solved(B.running_bond_wall(3, 3, dim=dim, mu=0.9))
    _set(monkeypatch, P, one_round_min_free=1)
    (label, n0), = step2_large.starts(P, sol, factors=(1.0,))
    step2_large.run_start(P, step2_large.build(P), n0, sol.alpha)
    assert seen == [warm]


def _forced_on_a_small_wall(monkeypatch, threshold, module, func, kwarg):
    """The route on the 3-course wall of test_small_wall_agrees_with_the_global_minimum with
    the setting ``threshold`` forced down to 1 block, recording the ``kwarg`` of each call of
    ``module.func``. Every verified start is a collapse state, so never below the MILP's global
    minimum, and the best one reaches it. Returns (the recorded values, the route's result)."""
    from limit.solve import milp

    P, sol = _solved(B.running_bond_wall(3, 2, dim=2, L=0.4, H=0.3, mu=0.9))
    seen = []
    real = getattr(module, func)
    monkeypatch.setattr(module, func, lambda *a, **k: seen.append(k.get(kwarg)) or real(*a, **k))
    _set(monkeypatch, P, **{threshold: 1})
    big = step2_large.solve(P, sol, workers=1)
    g = milp.global_minimum(P, sol.alpha, time_limit=300)
    assert g.status == "optimal" and big.ok
    assert big.alpha_worst >= g.alpha - 1e-7
    assert big.alpha == pytest.approx(g.alpha, rel=1e-6)
    return seen, big


@pytest.mark.slow  # about 3 s: the proximal iteration and the MILP on a small wall
def test_the_proximal_iteration_reaches_the_global_minimum_of_a_small_wall(monkeypatch):
    """The proximal iterative LP (large_prox, used from prox_min_free free blocks on) forced onto a
    small wall (:func:`_forced_on_a_small_wall`): every LP is proximal."""
    from limit.solve import iterative_lp

    seen, _ = _forced_on_a_small_wall(monkeypatch, "prox_min_free", iterative_lp, "solve", "prox")
    assert seen and all(p == DEFAULT.large_prox for p in seen)


@pytest.mark.slow  # about 2 s: the large route and the MILP on a small wall
def test_the_large_wall_snap_settings_reach_the_global_minimum_of_a_small_wall(monkeypatch):
    """The settings of very large walls (large_snap_comp_very_large, large_snap_plateau_very_large,
    "ratio" first, "least-slack" last, large_start_factors_very_large; from very_large_min_free free
    blocks on) forced onto a small wall
    (:func:`_forced_on_a_small_wall`): every snap asks for the large walls' rules, and the starts
    are those at 0.5 mu and 0.4 mu."""
    seen, big = _forced_on_a_small_wall(monkeypatch, "very_large_min_free", nlp, "finish", "rules")
    assert seen and all(r == ("ratio", "support", "least-slack") for r in seen)
    assert [r["start"] for r in big.starts] == ["lp-mu*0.5", "lp-mu*0.4"]


def test_the_routes_tuned_numbers_are_read_from_the_settings(monkeypatch):
    """The large route's starts, relaxation and LP cap come from the problem's settings (group
    "large"), not from module constants: with large_start_factors (0.5,) only the 0.5 mu start
    runs; with large_omega_2d 0.25 and large_max_iter 3 that start's first relaxation is 0.25 and
    it stops after 3 LPs at most."""
    from limit.solve import iterative_lp

    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, large_start_factors=(0.5,), large_omega_2d=0.25, large_max_iter=3,
         large_proximal_round=False)
    omegas, caps = [], []
    real = iterative_lp.solve

    def spy(*a, **k):
        omegas.append(k["omega"]())
        caps.append(k["max_iter"])
        return real(*a, **k)

    monkeypatch.setattr(iterative_lp, "solve", spy)
    out = step2_large.solve(P, sol, workers=1)
    assert [r["start"] for r in out.starts] == ["lp-mu*0.5"]
    assert omegas == [0.25] and caps == [3] and out.starts[0]["iterations"] <= 3


@pytest.mark.parametrize("grace", [0.0, 0.25])
def test_a_verified_start_stops_the_others_after_the_grace(monkeypatch, grace):
    """_Stop: a start that verifies t seconds into the route sets the stop time t0 + t (1 + grace)
    (the setting large_grace; 0: at once, the default; 0.25: a quarter of its time later); a start
    past it ends at
    its next LP, unverified, and says why (never a number)."""
    import time

    P, sol = _solved(B.running_bond_wall(4, 4, dim=2, L=0.4, H=0.3, mu=0.9))
    N = step2_large.build(P)
    t0 = time.perf_counter()
    stop = step2_large._Stop(t0 - 8.0, grace=grace)
    stop.verified(t0)  # verified 8 s into the route: the others stop 8 grace s later
    assert stop.at() == pytest.approx(t0 + 8.0 * grace, abs=1e-9)
    stop.verified(t0 + 100.0)  # a later one never moves it back
    assert stop.at() == pytest.approx(t0 + 8.0 * grace, abs=1e-9)
    stop.value.value = time.perf_counter() - 1.0
    r = step2_large.run_start(P, N, step2_large.start_nstar(P, sol, 0.5), sol.alpha, stop=stop)
    assert not r["verified"] and r["z"] is None and r["iterations"] == 1
    assert r["reason"].startswith("stopped: another start had verified")


@pytest.mark.slow  # about 18 s: the large route on a 3 x 3 wall, then the route choice several times
def test_small_scenes_keep_the_lower_of_the_two_routes(monkeypatch):
    """Below large_min_free, solver 'auto' runs the successive LP and then the large route, and
    keeps the large route's verified alpha only when it is lower; every run of both is listed.
    The successive LP is replaced by a stand-in that returns the large route's own verified
    point at a given alpha (or fails), so that only the choice is under test. (On the 70-stone
    Fig. 3 wall the large route verified 0.520808 where the successive LP kept the LP's
    0.570752: the setting also_iterative.)"""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    big = step2_large.solve(P, sol, workers=1)
    assert big.ok

    def stand_in(alpha, ok=True):
        def run(*a, **k):
            return RouteOutcome(ok, alpha, big.z, big.N, "" if ok else "forced",
                                [{"start": "lp", "solver": "sla", "alpha": alpha}], alpha_raw=alpha,
                                residuals=big.residuals, notes=["stand-in"], solver="sla", start="lp")
        return run

    cases = [(big.alpha, True, "successive-lp", big.alpha),  # not lower: the successive LP's stands
             (big.alpha + 0.05, True, "iterative-lp", big.alpha),  # lower: taken
             (big.alpha + 0.05, False, "iterative-lp", big.alpha)]  # the successive LP failed
    for alpha, ok, route, expected in cases:
        monkeypatch.setattr(step2, "run", stand_in(alpha, ok))
        part = step2.step2(P, sol, method="nlp")
        assert part["route"] == route and part["status"] == "optimal"
        assert part["alpha"] == pytest.approx(expected, abs=1e-12)
        assert [r["solver"] for r in part["runs"]] == ["sla"] + ["iterative-lp"] * len(big.starts)
    _set(monkeypatch, P, also_iterative=False)
    part = step2.step2(P, sol, method="nlp")
    assert part["route"] == "successive-lp" and [r["solver"] for r in part["runs"]] == ["sla"]


@pytest.mark.slow  # about 5 s: the bench's route comparison
def test_the_bench_auto_column_is_what_step2_keeps():
    """bench/step2_large_bench.py's 'auto' column, computed from the two routes it times, is the
    alpha step2.step2 itself returns for the same wall (the lower of the successive LP's and the
    large route's below large_min_free free blocks): the 'never worse than today' column."""
    from bench.step2_large_bench import auto_alpha

    P, sol = _solved(B.running_bond_wall(4, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    row = {"alpha": step2_large.solve(P, sol).alpha, "today_alpha": step2.run(P, sol).alpha}
    part = step2.step2(P, sol, method="nlp")
    assert part["status"] == "optimal"
    assert auto_alpha(row, P.n_dof // P.scene.ndof) == pytest.approx(part["alpha"], abs=1e-9)
    assert auto_alpha(row, P.n_dof // P.scene.ndof) <= row["today_alpha"] + 1e-12
    assert auto_alpha(row, DEFAULT.large_min_free) == row["alpha"]


@pytest.mark.parametrize("trust", [True, False])
def test_a_snap_whose_interior_point_pieces_all_diverge_asks_no_other_backend(monkeypatch, trust):
    """SNAP_TRUST_DIVERGED: when the interior point method's statics diverges on every rule's piece
    ("probably no feasible point"), Clarabel and HiGHS are not asked to prove it (at 10,050 2D
    blocks that proof took Clarabel 38 s per snap); with it off they are. The interior point is
    made to diverge here by a stand-in; every other backend runs for real."""
    P, sol = _solved(B.running_bond_wall(4, 4, dim=2, L=0.4, H=0.3, mu=0.9))
    N = step2_large.build(P)
    real, asked = step2_large.snap, []

    def snap(N_, z, rule="ratio", backend="highs", deadline=None):
        asked.append(backend)
        if backend == "ipm":
            return step2_large.Snap(None, f"piece LP statics ({rule}): interior point: mu grew", diverged=True)
        return real(N_, z, rule, backend, deadline)
    monkeypatch.setattr(step2_large, "snap", snap)
    monkeypatch.setattr(step2_large, "SNAP_TRUST_DIVERGED", trust)
    r = step2_large.run_start(P, N, step2_large.start_nstar(P, sol, 0.5), sol.alpha)
    assert "ipm" in asked and r["snaps"] >= 1
    assert ("clarabel" in asked) is not trust


@pytest.mark.slow  # 27 interior point LPs of 1,220 blocks and one snap
def test_a_wall_whose_statics_stay_degenerate_verifies_by_the_least_slack_snap():
    """The 1,220-block running-bond wall of issue 48 (units 0.25 x 0.1 m, mu 0.7; built with the
    wall generator as ``limit build wall --length 7.5 --height 4.0 --unit 0.25 0.12 0.1 --mu 0.7``),
    the LP's start alone. Its alpha settles while the normal forces keep moving on a degenerate
    optimal face, and the snaps of the "support" and "ratio" rules all fail there (without the
    third rule the start stalled at a residual of 3.5e-5 after 89 LPs: docs/performance.md). The
    "least-slack" rule must snap it to a point that passes the independent check, below the LP's
    alpha (an associative upper bound of every frictional collapse state)."""
    from scenes.generators import wall

    P, sol = _solved(wall(length=7.5, height=4.0, unit=(0.25, 0.12, 0.1), mu=0.7))
    assert P.n_dof // P.scene.ndof == 1220
    out = step2_large.solve(P, sol, factors=(1.0,), workers=1)
    assert out.ok, out.reason
    run = out.starts[0]
    assert run["verified"] and "least-slack" in run["how"], run
    ok, res, why = nlp.check(out.N, out.z, sol.alpha)
    assert ok, why
    assert out.alpha < sol.alpha * (1 - 1e-3)


def test_without_a_verified_point_the_large_route_goes_on_to_the_hard_budget(monkeypatch):
    """The large route keeps the successive LP's budget rule (limit.step2.run): with the budget
    spent before any start could run (1 microsecond) and hard_factor budgets still ahead, the
    starts run and one verifies, where a route stopped at the budget would return no point."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    _set(monkeypatch, P, large_min_free=1, nlp_time_budget=1e-6, hard_factor=1e9)
    part = step2.step2(P, sol, method="nlp")
    assert part["route"] == "iterative-lp"
    assert part["status"] == "optimal" and part["alpha"] <= sol.alpha * (1 + 1e-9)
    assert max(part["verification"].values()) < 1e-6


def test_a_start_that_verifies_after_the_budget_stops_the_others():
    """Past the budget (soft end) the first verified start ends the route: run one after
    another (workers=1), the starts after it are listed as not run; within the budget every
    start runs, for a lower point."""
    P, sol = _solved(B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.9))
    late = step2_large.solve(P, sol, time_budget=1e-6, hard_budget=600.0, workers=1)
    assert late.ok and late.starts[0]["verified"]
    assert len(late.starts) == 3 and all(r.get("not_run") for r in late.starts[1:])
    early = step2_large.solve(P, sol, time_budget=600.0, hard_budget=600.0, workers=1)
    assert early.ok and all(r["iterations"] > 0 for r in early.starts)
