"""Quasi-static pushover: settle under the dead load, then bracket the collapse
load factor alpha by load steps and bisection, at one or more contact
stiffnesses.

Pure Python (no YADE import): it drives any ``model`` with the methods of
:class:`dem_validation.engines.yade.yade_model.Model` (``set_alpha``, ``set_stiffness``,
``step``, ``residual``, ``max_motion``, ``snapshot``, ``restore``,
``displacements``, ``control_displacement``; attributes ``alpha``, ``eps``,
``dt``, ``kn``, ``length``, ``time_scale``), so the search itself is tested
without YADE.

A *trial* raises alpha from the last equilibrium to a target (linearly over
``ramp_T`` x T) and then steps, checking ``checks_per_T`` times per T:

* equilibrium: after at least ``observe_T`` x T (time for a slow run-away to
  show), every free block's out-of-balance force and moment are below
  ``eq_tol`` of its load plus its contact forces, and the largest block motion over the last check
  window is below ``motion_tol`` x eps x L (the elastic settlement);
* collapse: a block moved more than ``collapse_disp`` x eps^(1/3) x H since
  the last equilibrium (several times the motion up to the peak load of a
  rocking block at finite stiffness); or, once the first surge of motion that follows the load step
  has died down (motion per window below ``surge_drop`` x its peak), the
  motion picked up again: it has not shrunk for ``runaway_T`` x T and
  exceeds both ``rerun_frac`` x the surge peak and ``rerun_floor`` x eps x L
  (above the slow creep seen near equilibrium), and the blocks moved more
  than ``creep_disp`` x eps^(1/3) x L and more than ``rerun_reach`` x as far
  as before this rise began (new ground, not the next swing of an
  oscillation) - a slow run-away past the peak; or, after ``observe_T`` x T,
  the same rise with no surge ever over (near the collapse load the motion
  grows from the load step on), once the blocks moved ``early_disp`` x the
  collapse distance (a frictional slip of a few millimetres that then stops
  is not a collapse: the Fig. 5 trilithon read as one at 0.062 against 0.083);
* after ``trial_T`` x T without either: collapse when the motion per window
  is still growing (after the surge, or with no surge at all: a slow slide),
  equilibrium otherwise (the history says so).

On collapse the model goes back to the last equilibrium and the search
bisects, until hi - lo <= ``alpha_rtol`` x hi. L (m) is the mean free block
size, H (m) the size of the free part of the scene, T = sqrt(H / |g|) (s);
motions are translation plus rotation x block radius (m). The strain eps in these
limits is the model's ``detect_eps`` where it has one (the vertex model: the softest
run's, so that a stiffer run, whose frictional slips are no smaller, does not read a
sub-millimetre rearrangement as a run-away), else its contact strain.
"""
from __future__ import annotations

import math
import time

STABLE, COLLAPSE = "stable", "collapse"
#: softer-run equilibria tried in turn (highest first) as the start of a stiffer run
RESTIFFEN_TRIES = 3
#: at most this many re-tries of a bracket top that only a load step's jump collapsed
RECHECK_TRIES = 3


class Clock:
    """Progress reporting through ``emit(dict)`` every ``period`` steps (a step count, not the
    wall clock, so that every run of a job makes the same calls)."""

    def __init__(self, emit, period=1000):
        self.emit, self.period, self.last = emit, period, 0

    def tick(self, **info):
        step = int(info.get("step", 0))
        if step < self.last:  # a new search counts from 0
            self.last = step
        if self.emit is not None and step - self.last >= self.period:
            self.last = step
            self.emit(info)


def trial(model, a_from, a_to, p, clock=None, steps_before=0, rerun=True):
    """One load step from the equilibrium at ``a_from`` to ``a_to``.

    ``rerun=False`` turns the picked-up-motion rule off (after a change of
    stiffness the contacts spring back first). Returns a dict: outcome
    (stable|collapse), why, steps, residual, motion (m, largest block motion
    since the start), ref (snapshot at the start).
    """
    length, dt, T = model.length, model.dt, model.time_scale
    e = getattr(model, "detect_eps", None) or model.eps  # the strain that scales the motion limits
    collapse_disp = p["collapse_disp"] * e ** (1.0 / 3.0) * model.size
    creep_disp = p["creep_disp"] * e ** (1.0 / 3.0) * length
    early_disp = p["early_disp"] * collapse_disp
    motion_tol = p["motion_tol"] * e * length
    chk = max(1, int(round(T / dt / p["checks_per_T"])))
    ramp = int(round(p["ramp_T"] * T / dt))
    budget = max(chk, int(round(p["trial_T"] * T / dt)))
    observe = int(round(p["observe_T"] * T / dt))
    k_run = max(3, int(math.ceil(p["runaway_T"] * T / (chk * dt))))
    rerun_floor = p["rerun_floor"] * e * length
    ref = model.snapshot()
    prev = ref
    steps, res, d = 0, math.inf, 0.0
    w_last, w_peak = None, 0.0
    d_max, d_run = 0.0, 0.0  # largest motion so far; largest before the current rise began
    surge_over = False  # the first surge of motion after the load step has died down
    rising = 0          # check windows in a row whose motion did not shrink (by more than 1%)
    outcome = why = None
    while steps < budget:
        if steps < ramp:
            model.set_alpha(a_from + (a_to - a_from) * min(1.0, (steps + chk) / ramp))
        elif model.alpha != a_to:
            model.set_alpha(a_to)
        model.step(chk)
        steps += chk
        d = model.max_motion(ref)
        w = model.max_motion(prev)
        prev = model.snapshot()
        res = model.residual()
        if not surge_over:
            w_peak = max(w_peak, w)
            surge_over = w < p["surge_drop"] * w_peak
        if w_last is not None and w >= 0.99 * w_last:
            rising += 1
        else:
            rising, d_run = 0, d_max
        d_max = max(d_max, d)
        w_last = w
        if clock is not None:
            clock.tick(eps=model.eps, alpha=model.alpha, step=steps_before + steps, residual=res, motion=d)
        if d > collapse_disp:
            outcome, why = COLLAPSE, f"moved more than collapse_disp ({collapse_disp:.3g} m)"
            break
        if steps < ramp:
            continue
        if steps >= observe and res < p["eq_tol"] and w < motion_tol:
            outcome, why = STABLE, "equilibrium"
            break
        if (rerun and rising >= k_run and w > max(p["rerun_frac"] * w_peak, rerun_floor)
                and d > max(creep_disp, p["rerun_reach"] * d_run)):
            if surge_over:
                outcome, why = COLLAPSE, "motion picked up again after the first surge"
                break
            if steps >= observe and d > early_disp:
                outcome, why = COLLAPSE, "motion still growing since the load step"
                break
    if outcome is None:
        growing = rising >= 2 and (not surge_over or w > max(0.5 * p["rerun_frac"] * w_peak, rerun_floor))
        outcome = COLLAPSE if growing else STABLE
        why = "step budget spent, motion " + ("growing" if growing else "not growing")
    return {"outcome": outcome, "why": why, "steps": steps, "residual": res, "motion": d, "ref": ref}


class Search:
    """Load stepping and bisection at the model's current stiffness.

    ``history`` collects one record per trial: phase, alpha, outcome, why,
    steps, residual, motion (m), control (the live-load work-conjugate
    displacement from the settled state, m).
    """

    def __init__(self, model, p, clock=None, base=None, origin=None):
        self.model, self.p, self.clock = model, p, clock
        self.origin = origin  # snapshot of the unloaded scene: held_pose is measured from it
        self.history = []
        self.steps = 0
        self.base = base
        self.equilibria = []  # (alpha, snapshot) of every equilibrium reached by a load step
        self.held = None  # (alpha, the model's pair_forces) at the highest equilibrium of bracket
        self.held_pose = None  # per free block (u, rotation) at that equilibrium, from ``origin``

    def run(self, a_from, a_to, phase, rerun=True, ramp_T=None):
        """One trial; ``ramp_T`` (x T) overrides the knob of that name for this trial."""
        p = self.p if ramp_T is None else dict(self.p, ramp_T=max(self.p["ramp_T"], ramp_T))
        t = trial(self.model, a_from, a_to, p, self.clock, self.steps, rerun)
        self.steps += t["steps"]
        rec = {"phase": phase, "alpha": a_to, "outcome": t["outcome"], "why": t["why"], "steps": t["steps"],
               "residual": t["residual"], "motion": t["motion"]}
        if self.base is not None:
            rec["control"] = self.model.control_displacement(self.base)
        rec.update(self.model.stats())
        self.history.append(rec)
        return t

    def _hold(self, alpha):
        """Record the state at rest at ``alpha`` as the highest equilibrium so far."""
        self.held = (alpha, self.model.pair_forces())
        if self.origin is not None:
            self.held_pose = self.model.displacements(self.origin)

    def bracket(self, lo, step, first=None, first_ramp_T=None):
        """Raise alpha from the equilibrium at ``lo`` (first to ``first`` when given - ramped
        over ``first_ramp_T`` x T when given -, then by ``step``, growing by ``growth`` after
        each equilibrium) until a collapse, then bisect. Returns (lo, hi, collapse
        displacements of the last collapsing trial); hi is None when alpha_max was reached
        without collapse.

        A collapse read after a load step and never repeated by a bisection trial (every
        one held) may be the jump's dynamic overshoot, not the load: up to
        ``RECHECK_TRIES`` times, the bracket's top is tried again from the highest
        equilibrium, a step of at most alpha_rtol; when it holds there, loading goes on by
        ``restep`` x alpha. (Fig. 3-40 at eps 1e-5: a jump 0.24 -> 0.41 read as a collapse,
        every bisection held, and the run ended at 0.406 where its stiffer runs gave 0.56.)"""
        p, model = self.p, self.model
        collapse = hi = None
        hi_by_load = False  # hi comes from a load step and no bisection trial collapsed since
        rechecks = 0
        while True:
            ramp = None
            if hi is not None:
                if hi - lo <= p["alpha_rtol"] * hi:
                    if not (hi_by_load and rechecks < RECHECK_TRIES):
                        break
                    rechecks += 1
                    t = self.run(lo, hi, "recheck")
                    if t["outcome"] != STABLE:
                        collapse = model.displacements(t["ref"])
                        model.restore(t["ref"])
                        break
                    lo, hi, hi_by_load = hi, None, False
                    self.equilibria.append((lo, model.snapshot()))
                    self._hold(lo)
                    step = max(p["restep"] * lo, 1e-9)
                    continue
                a, phase = 0.5 * (lo + hi), "bisect"
            elif first is not None and first > lo:
                a, phase, first, ramp = min(first, p["alpha_max"]), "load", None, first_ramp_T
            else:
                if lo >= p["alpha_max"]:
                    break
                a, phase = min(lo + step, p["alpha_max"]), "load"
            t = self.run(lo, a, phase, ramp_T=ramp)
            if t["outcome"] == STABLE:
                lo = a
                self.equilibria.append((a, model.snapshot()))
                self._hold(a)
                # a full step (not one cut at alpha_max, not the first jump) lets the step grow
                if hi is None and phase == "load" and ramp is None and a > t["ref"]["alpha"] + 0.999 * step:
                    step *= p["growth"]
            else:
                collapse = model.displacements(t["ref"])
                model.restore(t["ref"])
                hi, hi_by_load = a, phase == "load"
        return lo, hi, collapse


def pushover(model, eps_list, p, emit=None, hint=None):
    """Bracket alpha at each settlement strain of ``eps_list`` (softest first).

    The first stiffness starts from the unloaded scene: settle under the dead load,
    then load steps of ``step0`` growing by ``growth``. A further stiffness starts
    from the previous one's highest equilibrium at or below ``restart_frac`` x its
    alpha_lo (a state well short of the peak, where the softer contacts' larger
    rotations do not matter), re-stiffened and re-equilibrated (if that state does not
    hold, the next lower one, up to ``RESTIFFEN_TRIES`` states); its first load step
    goes to ``rebracket`` x the previous alpha_hi (stiffer contacts carry more),
    further ones by ``restep`` x the previous alpha_lo. When
    there is no such state or it does not hold, that stiffness starts again from
    the unloaded scene. ``hint`` = (alpha_lo, alpha_hi) of a softer run made elsewhere
    (the vertex model's runs are separate models): a from-scratch start then goes
    straight to ``restart_frac`` x alpha_lo, ramped over ``jump_ramp_T`` x T (no dynamic
    overshoot), and on by ``restep`` x alpha_lo. Returns one dict per stiffness: eps, status
    (collapsed|stable), alpha (bracket midpoint, None unless collapsed), alpha_lo,
    alpha_hi, dead_load_collapse, history, steps, held_forces (where the model records them
    and the run collapsed: ``{"alpha", "pairs"}``, the contact forces per block pair at the
    highest equilibrium), held_pose (the run collapsed: per free block (u, rotation) at that
    equilibrium from the unloaded scene, m and rad; None otherwise), collapse (per free block
    (u, rotation) over the last collapsing trial, from the last equilibrium), dt, kn.
    """
    clock = Clock(emit)
    initial = model.snapshot()
    out = []
    prev = None  # (result, search) of the previous stiffness
    for eps in eps_list:
        model.set_stiffness(eps)
        search = Search(model, p, clock, origin=initial)
        clock.emit and clock.emit({"phase": "stiffness", "eps": eps, "dt": model.dt})
        start = None
        if prev is not None and prev[0]["status"] == "collapsed":
            lo_prev = prev[0]["alpha_lo"]
            below = sorted((e for e in prev[1].equilibria if e[0] <= p["restart_frac"] * lo_prev),
                           key=lambda e: -e[0])
            for a0, snap in below[:RESTIFFEN_TRIES]:
                model.restore(snap)
                search.base = prev[1].base
                t = search.run(a0, a0, "re-stiffen", rerun=False)
                if t["outcome"] == STABLE:
                    search.equilibria.append((a0, model.snapshot()))
                    start = (a0, max(p["restep"] * lo_prev, 1e-9), p["rebracket"] * prev[0]["alpha_hi"])
                    break
        if start is None:
            model.restore(initial, alpha=0.0)
            # after a softer run that carried the dead load, the stiffer contacts' first
            # spring-back is not read as a collapse (as in re-stiffening)
            t = search.run(0.0, 0.0, "settle", rerun=prev is None)
            if t["outcome"] != STABLE:
                out.append(_result(eps, model, search, "collapsed", None, 0.0, True, model.displacements(t["ref"])))
                prev = None
                continue
            search.base = model.snapshot()
            search.history[-1]["control"] = 0.0
            search.equilibria.append((0.0, search.base))
            start = (0.0, p["step0"], None)
            if hint is not None and prev is None and hint[0] and hint[0] > 0:
                start = (0.0, max(p["restep"] * hint[0], 1e-9), p["restart_frac"] * hint[0], p["jump_ramp_T"])
        lo, hi, collapse = search.bracket(*start)
        res = _result(eps, model, search, "stable" if hi is None else "collapsed", lo, hi, False, collapse)
        out.append(res)
        prev = (res, search)
    return out


def _result(eps, model, search, status, lo, hi, dead, collapse):
    alpha = 0.5 * (lo + hi) if (status == "collapsed" and lo is not None and hi is not None) else None
    out = {"eps": eps, "status": status, "alpha": alpha, "alpha_lo": lo, "alpha_hi": hi,
           "dead_load_collapse": dead, "history": search.history, "steps": search.steps,
           "collapse": collapse, "dt": model.dt, "kn": model.kn}
    if search.held is not None and search.held[1] is not None and status == "collapsed":
        out["held_forces"] = {"alpha": search.held[0], "pairs": search.held[1]}
    out["held_pose"] = search.held_pose if status == "collapsed" else None
    return out
