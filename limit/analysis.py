"""The two-step limit analysis of a scene: :class:`Analysis`, the typed result
(:class:`limit.results.typed.Result`, written as the result file of docs/formats.md, 'Result
file'), with the assembled problem and the LP solution it is made from.

Step 1: the checked associative LP (:mod:`limit.solve.checked_lp`). Step 2 (NLP,
:mod:`limit.step2`) is added by :func:`analyse` according to the method. The result's
parts are built by :mod:`limit.results.result_parts`.
"""
from __future__ import annotations

import dataclasses
import functools
import logging
import time
from dataclasses import dataclass
from functools import cached_property

from limit import settings, step2
from limit.solve.status import ANSWERED, Status
from limit.solve import lp as lpmod
from limit.model.assemble import Assembled, Options, assemble
from limit.solve.checked_lp import solve_lp, unsupported_blocks  # noqa: F401  (public here too)
from limit.solve.nlp import needs_nlp
from limit.results.result_parts import interfaces_part, lp_result  # noqa: F401
from limit.results.typed import Result, StepResult, Verdict

log = logging.getLogger(__name__)


#: units of every number in a result, whatever the scene file's ``units`` (converted on reading)
RESULT_UNITS = {"length": "m", "mass": "kg", "force": "N", "time": "s"}


@dataclass(frozen=True)
class Analysis:
    """One analysis: ``result``, the typed result, beside the objects it is made from: ``P``, the
    assembled problem, and ``sol``, step 1's LP solution. ``data`` is the result file's content
    (plain JSON-ready values only), made from ``result`` once."""

    result: Result
    P: Assembled
    sol: lpmod.LPSolution

    @cached_property
    def data(self) -> dict:
        return self.result.to_dict()


def analyse(scene, method: str = "auto", options: Options | None = None, solver: str = lpmod.DEFAULT_SOLVER,
            fallback: bool = True, check_kinematic: bool = False, nlp_options: dict | None = None,
            verdict: bool = True) -> Analysis:
    """Full analysis of a scene: its :class:`Analysis`, whose ``data`` is the result file of
    docs/formats.md, 'Result file' (without ``dem``).
    ``verdict`` False: no code check even where the scene states a demand (a caller that
    checks against another demand).

    BLAS runs on one thread meanwhile (threadpoolctl, restored on return): the dense algebra
    here is small (SLSQP, 2x2 to 6x6 blocks), runs are parallelised by process, and a
    multi-threaded OpenBLAS on a busy machine was measured to slow SLSQP down 300-fold."""
    if method not in ("lp", "nlp", "auto"):
        raise ValueError(f"method must be lp, nlp or auto, not {method!r}")
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options, verdict)


def _analyse(scene, method, options, solver, fallback, check_kinematic, nlp_options, verdict=True) -> Analysis:
    t0 = time.perf_counter()
    P = assemble(scene, options)
    sol, attempts, residuals = solve_lp(P, solver, fallback, check_kinematic)
    lp = StepResult.from_dict(lp_result(P, sol, attempts, residuals, time.perf_counter() - t0))
    if sol.status == Status.INFEASIBLE:
        lp = _with_dead_mechanism(P, lp)
    part = None
    log.info("%s: LP %s, alpha %s (%.1f s)", scene.name, sol.status, "-" if sol.alpha is None else f"{sol.alpha:.6g}",
             time.perf_counter() - t0)
    if method != "lp":
        t2 = time.perf_counter()
        part = step2.step2(P, sol, method=method, **(nlp_options or {}))
        log.info("%s: step 2 %s, alpha %s", scene.name, part.status,
                 "-" if part.alpha is None else f"{part.alpha:.6g}")
        st = settings.of(P)
        # the nearby starts below: small scenes with an LP optimum only
        nearby = sol.status == Status.OPTIMAL and len(scene.free) < st.large_min_free
        budget = _NearbyBudget(part, st, nlp_options, t2)
        if nearby and st.direction_starts_deg > 0 and _turnable(scene):
            deg = st.direction_starts_deg
            log.info("%s: step 2 with the live load turned by +-%g deg", scene.name, deg)
            part = _from_turned_directions(scene, P, sol, part, deg, options, budget)
        if nearby and st.friction_starts and not needs_nlp(P, sol)[0]:
            log.info("%s: step 2 at reduced friction", scene.name)
            part = _from_reduced_friction(P, sol, part, options, budget)
        if nearby and st.mirror_starts and _turnable(scene):
            part = _from_mirror(scene, P, sol, part, options, budget)
    lower_bound = None
    if P.I.bonded and sol.status == Status.OPTIMAL:  # with cohesion the frictional alpha has a lower bound
        from limit.solve import radenkovic

        lower_bound = radenkovic.lower_bound(P, solver)
    result = Result(scene.name, scene.dim, scene.n_blocks, int(len(scene.free)), len(P.I), lp, part,
                    dict(RESULT_UNITS), lower_bound)
    if verdict and scene.demand is not None:  # the code check, only for a scene that states a demand
        from limit.incremental_curve import follow_frictional
        from limit.verdict.local_check import scene_verdict

        v = scene_verdict(scene, result.to_dict(), sliding=functools.partial(follow_frictional, options=options))
        result = dataclasses.replace(result, verdict=Verdict.from_dict(v))
    return Analysis(result, P, sol)


class _NearbyBudget:
    """The step-2 keywords of the nearby starts, and what is left of step 2's hard budget for them.

    Once step 2 has a verified point, each nearby start has the budgets of a step 2 of its own.
    Without one, step 2 stops for good after ``hard_factor`` times its budget (the settings
    ``hard_factor`` and ``nlp_time_budget``, or the ``time_budget`` keyword), and its nearby
    starts share what is left of that: each begins only while time is left, with its own
    budget cut so that its hard limit ends there. ``t0``: perf_counter s at step 2's start."""

    def __init__(self, part: StepResult, st, nlp_options: dict | None, t0: float):
        self.nlp_options = {k: v for k, v in (nlp_options or {}).items() if k not in _NEARBY_DROP}
        budget = self.nlp_options.get("time_budget", step2.FROM_SETTINGS)
        budget = st.nlp_time_budget if budget == step2.FROM_SETTINGS else budget
        verified = part.status in ANSWERED and part.alpha is not None
        self.factor = st.hard_factor
        self.hard_s = None if verified or budget is None else st.hard_factor * float(budget)
        self.end = None if self.hard_s is None else t0 + self.hard_s

    def options(self) -> dict | None:
        """The step-2 keywords of one nearby start (the caller's, without :data:`_NEARBY_DROP`);
        None when no time is left."""
        if self.end is None:
            return dict(self.nlp_options)
        left = self.end - time.perf_counter()
        return None if left <= 0 else {**self.nlp_options, "time_budget": left / self.factor}

    def spent(self) -> str:
        """Why a nearby start does not begin."""
        return (f"not begun: no verified point, and step 2's hard budget ({self.factor:g} x its budget, "
                f"{self.hard_s:.0f} s) is spent")


def _turnable(scene) -> bool:
    """A 3D scene whose live load is body forces only (the direction sweep can turn it)."""
    return scene.dim == 3 and bool(scene.live) and all(ld.get("type") == "body_force" for ld in scene.live)


def _from_turned_directions(scene, P, sol, part: StepResult, deg: int, options, budget: _NearbyBudget) -> StepResult:
    """Step 2's part, also from the collapse states of the scene with its live load turned by
    +-``deg`` degrees about the vertical (the setting ``direction_starts_deg``): step 2 is a local
    search, and a state found under a nearby load direction can lie in a lower basin (Fig. 6:
    0.3608 from its own starts, 0.2195 from the +5 degree state). Each state is tried as a dynamic
    run's is (:func:`limit.step2.adopt_dem_state`) and adopted where it verifies lower; the part
    records them under ``direction_starts``."""
    from limit.model.scene import load_scene
    from limit.model.turned_load import turned

    sub_options = _sub_options(P, options, direction_starts_deg=0, friction_starts=False)
    t0 = time.perf_counter()

    def states():
        for turn in (deg, -deg):
            fields = {"turn_deg": turn}
            sub_nlp = budget.options()
            if sub_nlp is None:
                yield fields, None, budget.spent(), ""
                continue
            try:
                turned_scene = load_scene(turned(scene.data, turn))
            except Exception as exc:  # noqa: BLE001 - a direction that cannot be built is recorded, not fatal
                yield fields, None, f"{type(exc).__name__}: {exc}", ""
                continue
            sub = _analyse(turned_scene, "auto", sub_options, lpmod.DEFAULT_SOLVER, True, False, sub_nlp, False)
            yield fields, sub.result.nlp or {}, "", f"direction {turn:+g} deg"

    return _adopt_states(P, sol, part, states(), "direction_starts", t0)


def _from_reduced_friction(P, sol, part: StepResult, options, budget: _NearbyBudget) -> StepResult:
    """Step 2's part, also from the collapse states of step 2 (method nlp) with every friction
    coefficient and cohesion scaled by each factor of
    :data:`limit.solve.nlp_starts.FRICTION_FACTORS` (the setting ``friction_starts``), for a
    scene whose LP mechanism neither slides nor twists: there step 2 accepts the LP's point
    without a search (method auto), and its search (method nlp) starts from that rocking
    mechanism. At lower friction joints slide sooner, and a state in which some joints slide at
    zero normal force and others rock carries over to the full friction with the same alpha (the
    out-of-plane wall: t/H = 0.19048 from its own starts, 0.181726 from the state at 0.25 mu).
    Where the LP mechanism slides, step 2 already searches from reduced-friction LP starts, and
    on the catalog these states lowered nothing (docs/performance.md). Each state is tried as a
    dynamic run's is (:func:`limit.step2.adopt_dem_state`) and adopted where it verifies lower;
    the part records them under ``friction_starts``."""
    from limit.solve.nlp_starts import FRICTION_FACTORS

    sub_options = _sub_options(P, options, friction_starts=False, direction_starts_deg=0)
    t0 = time.perf_counter()

    def states():
        for f in FRICTION_FACTORS:
            sub_nlp = budget.options()
            if sub_nlp is None:
                yield {"factor": f}, None, budget.spent(), ""
                continue
            I2 = dataclasses.replace(P.I, mu=P.I.mu * f, cohesion=P.I.cohesion * f)
            P2 = assemble(P.scene, sub_options, interfaces=I2)
            sol2, _, _ = solve_lp(P2)
            if sol2.status != Status.OPTIMAL:
                yield {"factor": f}, None, f"the LP there: {sol2.status}", ""
                continue
            yield {"factor": f}, step2.step2(P2, sol2, method="nlp", **sub_nlp), "", f"friction x {f:g}"

    return _adopt_states(P, sol, part, states(), "friction_starts", t0)


def _from_mirror(scene, P, sol, part: StepResult, options, budget: _NearbyBudget) -> StepResult:
    """Step 2's part, also from the collapse state of the scene under its live load reversed,
    reflected by the vertical mirror across the load (the setting ``mirror_starts``;
    :mod:`limit.model.reversal_mirror`), for a scene that this mirror maps onto itself; the part
    unchanged for any other. Step 2 is a local search, and under the reversed load it can reach a
    state that it misses under the scene's own (the catalog's wall-3x3-3d out of its plane: the LP's
    0.5 at 90 deg, 6/13 at 270 deg); reflected, that state is one of the scene's at the same alpha.
    It is tried as a dynamic run's is (:func:`limit.step2.adopt_dem_state`) and adopted where it
    verifies lower; the part records it under ``mirror_starts``."""
    from limit.model import reversal_mirror
    from limit.model.scene import load_scene
    from limit.model.turned_load import turned

    mirror = reversal_mirror.find(scene, P.I)
    if mirror is None:
        return part
    log.info("%s: step 2 under the reversed live load, mirrored", scene.name)
    sub_options = _sub_options(P, options, mirror_starts=False, direction_starts_deg=0)
    t0 = time.perf_counter()

    def states():
        sub_nlp = budget.options()
        if sub_nlp is None:
            yield {"load": "reversed"}, None, budget.spent(), ""
            return
        try:
            reversed_scene = load_scene(turned(scene.data, 180.0))
        except Exception as exc:  # noqa: BLE001 - a scene that cannot be built reversed is recorded, not fatal
            yield {"load": "reversed"}, None, f"{type(exc).__name__}: {exc}", ""
            return
        sub = _analyse(reversed_scene, "auto", sub_options, lpmod.DEFAULT_SOLVER, True, False, sub_nlp, False)
        nlp = sub.result.nlp or {}
        if nlp.get("mechanism"):
            nlp = nlp.updated(mechanism=mirror.mechanism(scene, nlp["mechanism"]))
        yield {"load": "reversed"}, nlp, "", "mirrored reversed-load"

    return _adopt_states(P, sol, part, states(), "mirror_starts", t0)


#: step-2 keywords that a nearby start's own analysis does not take
_NEARBY_DROP = ("dem_state", "global_check", "iterative")


def _sub_options(P, options, **off) -> Options:
    """The options of a nearby start's own analysis: P's settings with ``off`` changed (the nearby
    starts that must not recurse)."""
    return dataclasses.replace(options or Options(), settings=settings.of(P).replace(**off))


def _adopt_states(P, sol, part: StepResult, states, key: str, t0: float) -> StepResult:
    """Step 2's part with each collapse state of ``states`` tried as a dynamic run's is
    (:func:`limit.step2.adopt_dem_state`) and adopted where it verifies lower, the attempts listed
    under ``key``. ``states`` yields (fields, nlp, failure, source): the fields naming the attempt,
    the step-2 part found there (None when ``failure`` says why there is none) and the source
    recorded with an adopted state. The part's own ``dem_start`` entry is kept; ``time_s`` grows by
    the time since ``t0`` (perf_counter s)."""
    own_dem = part.get("dem_start")
    entries = []
    for fields, nlp, failure, source in states:
        if nlp is None:
            entries.append({**fields, "status": Status.FAILED, "reason": failure})
            continue
        if nlp.get("status") not in ANSWERED or not nlp.get("mechanism"):
            entries.append({**fields, "status": Status.FAILED, "alpha_there": nlp.get("alpha"),
                            "reason": f"step 2 there: {nlp.get('status')}"})
            continue
        part, entry = step2.adopt_dem_state(P, sol, part, {"displacement": nlp["mechanism"], "source": source})
        entries.append({**fields, "alpha_there": nlp.get("alpha"),
                        **{k: entry.get(k) for k in ("status", "alpha", "adopted", "reason")}})
    part = part.without("dem_start")
    if own_dem is not None:
        part = part.updated(dem_start=own_dem)
    return part.updated(**{key: entries}, time_s=(part.time_s or 0.0) + time.perf_counter() - t0)


def _with_dead_mechanism(P, lp: StepResult) -> StepResult:
    """An "infeasible" LP part with the dead-load mechanism (:mod:`limit.solve.dead_mechanism`) as
    ``dead_load_mechanism`` and its blocks and joints named in the reason (a new part; ``lp``
    itself where there is no such mechanism)."""
    from limit.solve import dead_mechanism

    u = dead_mechanism.solve(P)
    if u is None:
        return lp
    part = dead_mechanism.describe(P, u)
    return lp.updated(dead_load_mechanism=part,
                      reason=f"{lp.reason or 'the dead load alone cannot be carried'}; {dead_mechanism.phrase(part)}")

