"""Step 2 at scale: the iterative LP on the structured interior point method, snapped to
an exactly complementary point and checked independently.

Route (for scenes too large for the successive LP of :mod:`limit.solve.nlp`, and for
scenes whose associative LP has no mechanism):

1. The iterative LP of Gilbert, Casapulla & Ahmed (2006) with the friction
   capacities ``mu N*`` as the right-hand side of :mod:`limit.solve.ipm`
   (:func:`limit.solve.iterative_lp.solve`, backend "ipm"), N* relaxed by omega (the settings
   ``large_omega_2d``, ``large_omega_3d``), halved whenever the complementarity residual has no
   new low for ``large_stall`` LPs (``large_stall_very_large`` from ``very_large_min_free`` free
   blocks on, 2D).
   Each LP answer is a point of the frictional problem: its statics, and as
   its dual the mechanism with flow ``G lam`` (no dilatancy).
2. After each LP the point is checked (:func:`limit.solve.nlp.check`); once its
   complementarity residual is below ``large_snap_comp`` the piece LP
   (:func:`limit.solve.nlp.polish`: faces that flow keep s = 0, the others lam = 0)
   snaps it to an exactly complementary point, which is checked in turn. A
   failed snap is retried only when the residual has fallen tenfold. A residual
   that stops falling (no new low for ``large_plateau`` LPs) below ``large_snap_plateau`` has
   its best iterate snapped too. From ``very_large_min_free`` free blocks on (2D), both
   thresholds are lower (``large_snap_comp_very_large``, ``large_snap_plateau_very_large``):
   a failed snap costs there several LPs.
   From ``prox_min_free`` free blocks on (2D), each LP is the proximal QP of
   :func:`limit.solve.iterative_lp.solve` (``prox``, the setting ``large_prox``): the normal
   forces are pulled toward N*, so that the statics stop jumping across a degenerate optimal face.
3. Several starts (the normal forces of the associative LP at mu x ``large_start_factors``:
   mu, 0.5 mu and 0.25 mu), one per core at once, each solving its own reduced-friction LP; from
   ``one_round_min_free`` free blocks on, only as many as there are cores (from
   ``very_large_min_free`` on in 2D, ``large_start_factors_very_large``). The
   lowest verified alpha is kept. Each verified alpha is a
   non-associative collapse state: an upper bound of the global frictional
   minimum, not the minimum itself.
4. In 2D below ``prox_min_free`` free blocks (plain LPs), where no start verifies, the same
   starts run again with each LP the proximal QP (``large_prox``; the setting
   ``large_proximal_round``), while the budget lasts: on a 3,098-block wall of the wall family
   the plain iteration stalls and the proximal one verifies, on a 626-block one the reverse
   (docs/performance.md, 'A second round with the proximal QP'). In 3D, where it rescued
   neither a 1,295-block wall nor the imported dome, the second round is a patient one instead:
   the stall count and the LP cap ``large_patience_round_3d`` times the settings', with which
   that wall verifies.

When the associative LP is unbounded (sliding needs dilatancy, e.g. a block
wedged between two fixed surfaces), the first N* comes from an equilibrium of
the dead load alone (alpha = 0).

The size thresholds and the tuned numbers named above are settings (:mod:`limit.settings`,
groups "route" and "large"), read from the problem's options; the structural choices below
(snap rules and backends, the dimensions a rule applies in) are the route's own.

Measured times and alphas (running-bond walls, ``make bench``: bench/step2_large_bench.py) are in
docs/performance.md, 'Step 2 at scale'.
"""
from __future__ import annotations

import logging
import time
from typing import NamedTuple

import numpy as np

from limit import settings
from limit.solve.status import IterativeStatus, Status
from limit.solve import iterative_lp, lpsub, nlp, nlp_starts, piece_statics, rigid_clusters
from limit.solve.nlp_problem import build
from limit.solve.outcome import RouteOutcome

log = logging.getLogger(__name__)

#: flowing-face rules of the snap, in order, and whether the first one passing the check is kept;
#: the "least-slack" rule: the flowing faces are those of the mechanism closest to complementary
#: with the iterate's statics (:func:`limit.solve.rigid_clusters.least_slack_flow`: least work on
#: the faces' slacks), where its multiplier exceeds the setting large_least_slack_support of the
#: largest (the independent check judges the compatibility left). It is tried last: where the
#: statics' optimal face is degenerate (the normal forces keep moving at a settled alpha),
#: "support" holds more faces at their limit than a statics can, and "ratio" keeps too few for a
#: mechanism
SNAP_RULES = ("support", "ratio", "least-slack")
SNAP_FIRST = True
#: from the setting very_large_min_free free blocks on, in these dimensions (2D only: no 3D wall
#: reaches it in the benchmarks), the snap thresholds of the settings large_snap_comp_very_large and
#: large_snap_plateau_very_large apply, with "ratio" first: a failed snap costs there more than
#: several LPs
VERY_LARGE_DIMS = (2,)
SNAP_RULES_LARGE = ("ratio", "support", "least-slack")
#: LP backends of the snap's piece LPs, tried in turn until one gives a point that passes the
#: check; when a backend proves every rule's piece LP infeasible, the next is not asked. "ipm": the
#: statics on the structured interior point method (:mod:`limit.solve.piece_statics`), which proves
#: nothing infeasible (it stops when its iterates diverge)
SNAP_BACKENDS = ("ipm", "clarabel", "highs")
#: a piece whose interior point diverges (ipm.solve's ``mu_diverged``: "probably no feasible
#: point") counts as infeasible, like a piece a backend proved infeasible
SNAP_TRUST_DIVERGED = True
#: LP backend of the snap's kinematics on rigid clusters (and of the least-slack mechanism)
KINEMATICS_BACKEND = "clarabel"
#: from the setting one_round_min_free free blocks on (where only as many starts run as there are
#: workers), in these dimensions, each LP starts from the last one's point (iterative_lp's
#: ``warm_start``)
WARM_START_DIMS = (2,)

def _free_blocks(P) -> int:
    return P.n_dof // P.scene.ndof


def _one_round(P) -> bool:
    """At least one_round_min_free free blocks: one round of starts, relaxation at most
    large_omega_one_round."""
    return _free_blocks(P) >= settings.of(P).one_round_min_free


def _proximal_by_size(P) -> bool:
    """Whether each LP of a start is the proximal QP from the first round: 2D, from
    prox_min_free free blocks on."""
    return P.scene.dim == 2 and _free_blocks(P) >= settings.of(P).prox_min_free


def _very_large(P) -> bool:
    """At least very_large_min_free free blocks, in a dimension of VERY_LARGE_DIMS."""
    return _free_blocks(P) >= settings.of(P).very_large_min_free and P.scene.dim in VERY_LARGE_DIMS


def _snap_settings(P) -> tuple[float, float, tuple]:
    """(residual below which to snap, plateau below which to snap, flowing-face rules) for P's size."""
    cfg = settings.of(P)
    if _very_large(P):
        return cfg.large_snap_comp_very_large, cfg.large_snap_plateau_very_large, SNAP_RULES_LARGE
    return cfg.large_snap_comp, cfg.large_snap_plateau, SNAP_RULES


def dead_load_start(P) -> np.ndarray | None:
    """Scaled interface actions in equilibrium with the dead load alone (alpha = 0) within the
    yield domain, or None when there are none (the dead load alone collapses)."""
    import scipy.sparse as sp

    nx = P.model.n_x
    res = lpsub.solve(np.zeros(nx), sp.csr_matrix(P.Eh), -P.f0h, sp.csr_matrix(P.Yh), P.kh,
                      np.full(nx, -np.inf), np.full(nx, np.inf), "highs")
    return res.z if res.ok else None


def start_label(factor: float) -> str:
    return "lp" if factor == 1.0 else f"lp-mu*{factor:g}"


def nstar_of(P, x: np.ndarray) -> np.ndarray:
    """N* per friction row (scaled) of the interface actions ``x`` (n_x,) in N and N m: each
    row's normal force."""
    _, _, ncol, _ = iterative_lp.friction_rows(P)
    return (np.asarray(x, dtype=float) / P.Dx)[ncol]


def start_nstar(P, lp_sol, factor: float) -> np.ndarray | None:
    """N* per friction row of the start at ``factor``: the normal forces of the associative LP at
    mu x factor (the LP's own at factor 1); None when that LP has no optimum."""
    if factor == 1.0:
        return nstar_of(P, lp_sol.x)
    sol2 = nlp_starts.reduced_friction_lp(P, factor)
    return None if sol2 is None else nstar_of(P, sol2.x)


def starts(P, lp_sol, factors=None) -> list[tuple[str, np.ndarray]]:
    """(label, N* per friction row) of each start (:func:`start_nstar`; ``factors`` default: the
    setting large_start_factors), or of a dead-load equilibrium when the LP has no optimum."""
    if lp_sol is None or lp_sol.status != Status.OPTIMAL:
        _, _, ncol, _ = iterative_lp.friction_rows(P)
        xh = dead_load_start(P)
        return [] if xh is None else [("dead-load", xh[ncol])]
    factors = settings.of(P).large_start_factors if factors is None else factors
    out = [(start_label(f), start_nstar(P, lp_sol, f)) for f in factors]
    return [(lab, n0) for lab, n0 in out if n0 is not None]


class Snap(NamedTuple):
    """The outcome of :func:`snap`: the snapped point ``z`` (None on failure; not yet checked),
    ``note`` (how, or why it failed), ``infeasible``: an LP backend proved that the piece LP has no
    point (its kinematics or statics infeasible or unbounded: the flowing faces guessed wrong,
    no other backend can do better), ``diverged``: the structured interior point method's
    iterates diverged on the statics, which an infeasible piece does (no proof)."""
    z: np.ndarray | None
    note: str
    infeasible: bool = False
    diverged: bool = False


def snap(N, z, rule: str = "ratio", backend: str = "highs", deadline: float | None = None) -> Snap:
    """The piece LP of :func:`limit.solve.nlp.polish`, solved as its two independent parts: with the
    flowing faces fixed, ``min alpha`` involves only the statics (alpha, xh: equilibrium,
    s = 0 on the flowing faces, s >= 0 elsewhere) and the kinematics (vh, lamh >= 0 on the
    flowing faces, 0 elsewhere: flow and normalisation) is a feasibility problem. The kinematics
    first, on rigid clusters (:mod:`limit.solve.rigid_clusters`: an LP of a few thousand unknowns
    at most, solved by :data:`KINEMATICS_BACKEND`), so that a flowing set without a mechanism costs
    no statics LP; then the statics, an LP of the whole scene's actions: ``backend`` "ipm" on the
    structured interior point method (:mod:`limit.solve.piece_statics`), else in that backend of
    :mod:`limit.solve.lpsub` (1,008-block wall: 21 s as one LP). ``deadline``
    (time.perf_counter(), None: none): each LP stops there (a failed snap). Clarabel's
    reduced-accuracy answers are taken (the snapped point is checked independently): on a 3D
    wall of 3,024 blocks both piece LPs ended "AlmostSolved" at a residual of 2.4e-3."""
    import scipy.sparse as sp

    def left():
        return None if deadline is None else deadline - time.perf_counter()

    P = N.P
    if rule == "least-slack":  # the kinematics first, on every face; its support flows
        s = np.maximum(N.slack(z), 0.0)
        kin = rigid_clusters.least_slack_flow(P, N.Gh, s / max(s.max(initial=0.0), 1e-300), KINEMATICS_BACKEND,
                                              time_limit=left())
        if kin.vh is None:
            return Snap(None, f"least-slack mechanism: {kin.status}", infeasible=kin.no_point)
        flows = kin.lam > settings.of(P).large_least_slack_support * max(kin.lam.max(initial=0.0), 1e-300)
        act, hold = np.flatnonzero(flows), np.flatnonzero(~flows)
        vh, lamh = kin.vh, np.where(flows, kin.lam, 0.0)
    else:
        flows = nlp.flowing_faces(N, z, rule)
        act, hold = np.flatnonzero(flows), np.flatnonzero(~flows)
        # kinematics on the rigid clusters of blocks that the faces that do not flow leave (a small LP)
        kin = rigid_clusters.kinematics(P, N.Gh, flows, KINEMATICS_BACKEND, time_limit=left())
        if kin.vh is None:
            return Snap(None, f"piece LP kinematics ({rule}): {kin.status}", infeasible=kin.no_point)
        vh = kin.vh
        lamh = np.zeros(P.model.n_faces)
        lamh[act] = kin.lam
    if backend == "ipm" and P.bonded:  # piece_statics eliminates homogeneous flowing faces only
        backend = "clarabel"
    if backend == "ipm":  # the statics on the structured interior point method
        t = left()
        if t is not None and t <= 0:
            return Snap(None, f"piece LP statics ({rule}): time limit reached before the LP")
        st = piece_statics.solve(P, flows)
        if st.alpha is None:
            return Snap(None, f"piece LP statics ({rule}): {st.note}", diverged=st.diverged)
        return Snap(N.join(st.alpha, st.xh, vh, lamh),
                    f"piece LP ({rule}, in two parts; statics {st.note}) with {act.size} flowing faces")
    nx = P.model.n_x
    # statics: [alpha, xh]
    col = sp.csr_matrix(P.fLh.reshape(-1, 1))
    Yh = sp.csr_matrix(P.Yh)
    Aeq = sp.vstack([sp.hstack([col, P.Eh]), sp.hstack([sp.csr_matrix((act.size, 1)), Yh[act]])]).tocsr()
    beq = np.concatenate([-P.f0h, P.kh[act]])
    Aub = sp.hstack([sp.csr_matrix((hold.size, 1)), Yh[hold]]).tocsr()
    c = np.zeros(1 + nx)
    c[0] = 1.0
    lo = np.full(1 + nx, -np.inf)
    lo[0] = 0.0
    st = lpsub.solve(c, Aeq, beq, Aub, P.kh[hold], lo, np.full(1 + nx, np.inf), backend, time_limit=left(),
                     almost=True)
    if not st.ok:
        return Snap(None, f"piece LP statics ({rule}): {st.status}", infeasible=st.no_point)
    return Snap(N.join(st.z[0], st.z[1:], vh, lamh), f"piece LP ({rule}, in two parts) with {act.size} flowing faces")


def run_start(P, N, nstar0, alpha_ref, deadline=None, max_iter=None, backend=None, stop=None,
              proximal: bool | None = None, patience: float = 1.0) -> dict:
    """One start: iterate (at most ``max_iter`` LPs, default the setting large_max_iter), check
    each LP point, snap near complementarity (with the LP ``backend`` of :mod:`limit.solve.lpsub`,
    default each of :data:`SNAP_BACKENDS` in turn). ``proximal``: each LP is the proximal QP
    (the setting large_prox) or not (None: :func:`_proximal_by_size`); ``patience``: the stall count
    and the default LP cap are this many times the settings'. ``stop``
    (a :class:`_Stop`, None: none): the time another start set for every start to stop (it ends
    this one like its deadline), which this one sets in turn when it verifies. Returns
    {"verified", "alpha", "z", "iterations", "snaps", "how", "time_s", "reason"}."""
    t0 = time.perf_counter()
    cfg = settings.of(P)

    def until():  # the earlier of the deadline and the shared stop time; None: neither
        ends = [t for t in (deadline, None if stop is None else stop.at()) if t is not None and np.isfinite(t)]
        return min(ends, default=None)
    backends = SNAP_BACKENDS if backend is None else (backend,)
    found: dict = {}
    snaps = [0]
    stalled: list = []
    snap_comp, snap_plateau, rules = _snap_settings(P)
    retry_below = [snap_comp]
    snapped_at = [np.inf]  # the lowest residual a snap was tried at
    omega = cfg.large_omega_2d if P.scene.dim == 2 else cfg.large_omega_3d
    stall = round(patience * (cfg.large_stall_very_large if _very_large(P) else cfg.large_stall))
    relax = {"omega": min(omega, cfg.large_omega_one_round) if _one_round(P) else omega, "best": np.inf,
             "best_it": 0, "z": None}

    def try_snap(z, comp, it) -> bool:
        snaps[0] += 1
        snapped_at[0] = min(snapped_at[0], comp)
        for bk in backends:
            proven = []  # piece LPs this backend proved infeasible (no other backend can do better)

            def polisher(N_, z_, rule="ratio", backend="highs"):
                out = snap(N_, z_, rule, backend, until())
                if out.z is None and (out.infeasible or SNAP_TRUST_DIVERGED and out.diverged):
                    proven.append(rule)
                return out.z, out.note

            zf, ok, _, _, note = nlp.finish(N, z, alpha_ref, bk, polisher=polisher, unpolished=False,
                                            rules=rules, first=SNAP_FIRST)
            if ok:
                found.update(z=zf, how=f"{note}, {bk}", it=it)
                return True
            if len(set(proven)) == len(rules):  # 3,052 blocks: HiGHS took 43 s to agree
                break
        return False

    def on_iterate(it, r, nstar):
        z = N.join(r["alpha"], r["xh"], r["vh"], r["lamh"])
        ok, res, _ = nlp.check(N, z, alpha_ref)
        if ok:
            found.update(z=z, how="iterate", it=it)
            return True
        comp = res["complementarity"]
        if comp < relax["best"]:
            relax.update(best=comp, best_it=it, z=z)
        elif (it - relax["best_it"] == cfg.large_plateau and relax["best"] < min(snap_plateau, snapped_at[0])
              and try_snap(relax["z"], relax["best"], relax["best_it"])):
            return True
        if it - relax["best_it"] >= stall and relax["omega"] > cfg.large_omega_min:
            relax.update(omega=relax["omega"] / 2.0, best_it=it)
        elif it - relax["best_it"] >= stall:  # no new low at the smallest relaxation
            stalled.append(it)
            return True
        if comp < retry_below[0]:
            if try_snap(z, comp, it):
                return True
            retry_below[0] = comp / 10.0
        end = until()
        return end is not None and time.perf_counter() > end

    near = cfg.large_lp_tol_near_2d if P.scene.dim == 2 else None  # None: ipm's own tolerance
    out = iterative_lp.solve(P, None, omega=lambda: relax["omega"], tol=1e-10,
                             max_iter=round(patience * cfg.large_max_iter) if max_iter is None else max_iter,
                             backend="ipm",
                             nstar0=nstar0, on_iterate=on_iterate,
                             lp_tol=lambda: cfg.large_lp_tol_far if relax["best"] > cfg.large_far_comp else near,
                             warm_start=_one_round(P) and P.scene.dim in WARM_START_DIMS,
                             prox=cfg.large_prox if (_proximal_by_size(P) if proximal is None else proximal)
                             else None)
    rec = {"iterations": out.iterations, "snaps": snaps[0], "time_s": time.perf_counter() - t0,
           "omega": relax["omega"]}
    if found:
        if stop is not None:
            stop.verified(time.perf_counter())
        return {**rec, "verified": True, "alpha": float(found["z"][N.ia]), "z": found["z"], "how": found["how"]}
    if stalled:
        why = (f"stalled: the complementarity residual had no new low ({relax['best']:.1e}) for "
               f"{stall} LPs at the smallest relaxation {cfg.large_omega_min:g}")
    elif stop is not None and time.perf_counter() > stop.at() and (deadline is None or stop.at() < deadline):
        grace = stop.grace
        why = f"stopped: another start had verified ({grace:.0%} of its time given to the others)" if grace \
            else "stopped: another start had verified first"
    else:
        why = out.reason or ("time budget spent" if out.status == IterativeStatus.STOPPED else out.status)
    return {**rec, "verified": False, "alpha": out.alpha, "z": None, "how": None, "reason": why}


class _Stop:
    """The time (time.perf_counter(), shared by the starts' processes) at which every start stops:
    infinite until a start verifies at t, then t0 + (t - t0) (1 + grace) with t0 the route's start
    (the setting large_grace), or, given ``soft`` (the end of the route's budget), the later of ``soft`` and
    t: the others go on to the budget's end for a lower point, and no further once one has
    verified. ``value``: a multiprocessing.Value("d") for starts in worker processes (created
    before they fork), else a plain holder."""

    def __init__(self, t0: float, value=None, soft: float | None = None, grace: float = 0.0):
        self.t0 = t0
        self.soft = soft
        self.grace = grace
        self.value = value if value is not None else type("Holder", (), {"value": np.inf})()

    def at(self) -> float:
        return float(self.value.value)

    def verified(self, t: float) -> None:
        end = self.t0 + (t - self.t0) * (1.0 + self.grace) if self.soft is None else max(self.soft, t)
        self.value.value = min(self.at(), end)


def _round(P, lp_sol, plan, alpha_ref, deadline, N, workers, t0, soft, opts) -> tuple[int, list]:
    """One round of the starts of ``plan``: (workers used, one result per start), in parallel
    when ``workers`` > 1 and processes can be started, else one after another. ``t0`` (None:
    the starts do not stop each other) and ``soft``: see :class:`_Stop`; ``opts``: keywords of
    :func:`run_start` for every start of the round (``proximal``, ``patience``)."""
    if workers > 1:
        results = _run_parallel(P, lp_sol, plan, alpha_ref, deadline, workers, t0, soft, opts)
        if results is not None:
            return workers, results
    results = []
    stop = _Stop(t0, soft=soft, grace=settings.of(P).large_grace) if t0 is not None else None
    for label, start in plan:
        if deadline is not None and any(r["verified"] for r in results) and \
                time.perf_counter() > (deadline if soft is None else soft):
            results.append(_not_run("time budget spent"))
            continue
        results.append(_start_job((P, lp_sol, start, alpha_ref, deadline, N, stop, opts)))
    return 1, results


def _rounds(P) -> list:
    """The route's rounds of starts, as (keywords of :func:`run_start`, label suffix, what it
    does): the first, then, run only where no start of the first verifies, in 2D below
    prox_min_free free blocks the proximal one (large_proximal_round), in 3D the patient one
    (large_patience_round_3d)."""
    cfg = settings.of(P)
    rounds = [({}, "", "")]
    if P.scene.dim == 2 and not _proximal_by_size(P) and cfg.large_proximal_round:
        rounds.append(({"proximal": True}, " (proximal)", "each LP the proximal QP"))
    elif P.scene.dim == 3 and cfg.large_patience_round_3d > 1.0:
        f = cfg.large_patience_round_3d
        rounds.append(({"patience": f}, " (patient)", f"{f:g} times as patient"))
    return rounds


def _not_run(why: str) -> dict:
    return {"verified": False, "not_run": True, "reason": why, "z": None, "iterations": 0, "snaps": 0,
            "time_s": 0.0}


def _start_job(args) -> dict:
    """One start in a worker process (top level, so that it pickles): its N* (a factor's
    associative LP is solved here, in parallel with the other starts', or it is given) and the
    iteration. ``deadline``: absolute time.perf_counter() (CLOCK_MONOTONIC on Linux: the same
    clock in every process), so a start that waited for a free worker gets only what is left
    of the run's budget. ``N``: the problem built already (None in a worker: built there)."""
    P, lp_sol, start, alpha_ref, deadline, N, stop, opts = args
    if stop is None and _SHARED_STOP is not None:  # a worker process: the route's shared stop time
        stop = _SHARED_STOP
    if deadline is not None and time.perf_counter() > deadline:
        return _not_run("time budget spent")
    if stop is not None and time.perf_counter() > stop.at():
        return _not_run("another start had verified")
    nstar0 = start_nstar(P, lp_sol, start) if isinstance(start, float) else start
    if nstar0 is None:
        return _not_run(f"the associative LP at mu x {start:g} has no optimum")
    return run_start(P, build(P) if N is None else N, nstar0, alpha_ref, deadline=deadline, stop=stop,
                     **(opts or {}))


#: the route's stop time in a worker process (set by _init_worker when the pool forks)
_SHARED_STOP = None


def _init_worker(stop) -> None:
    global _SHARED_STOP
    _SHARED_STOP = stop


def _run_parallel(P, lp_sol, plan, alpha_ref, deadline, workers, t0=None, soft=None, opts=None) -> list | None:
    """Every start at once in ``workers`` processes; None when processes cannot be started
    here (e.g. inside a daemonic worker): the caller then runs them one after another. ``t0``
    (None: the starts do not stop each other): the route's start, for the shared :class:`_Stop`
    (with ``soft``, its soft end). ``opts``: see :func:`_round`."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    ctx = mp.get_context("fork")
    try:
        stop = None if t0 is None else _Stop(t0, ctx.Value("d", np.inf), soft, settings.of(P).large_grace)
        with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                                 initargs=(stop,)) as ex:
            return list(ex.map(_start_job, [(P, lp_sol, s, alpha_ref, deadline, None, None, opts)
                                            for _, s in plan]))
    except (OSError, AssertionError, RuntimeError):
        return None


def solve(P, lp_sol, time_budget: float | None = None, factors=None, workers: int | None = None,
          hard_budget: float | None = None) -> RouteOutcome:
    """The large-scale route of step 2: every start run (until the budget is spent), the
    lowest verified alpha kept. ``workers``: processes for the starts (default: one per core,
    at most one per start; 1 runs them one after another). ``hard_budget`` (s, above
    ``time_budget``; None: the same): while no start has verified, the starts go on past
    ``time_budget`` up to it, and once one verifies after ``time_budget`` the others stop (the
    successive LP's rule, :func:`limit.step2.run`). Returns its :class:`RouteOutcome` (``starts``:
    one entry per start; the best verified point's ``alpha``, ``z``, ``start``, ``residuals``)."""
    import os

    t0 = time.perf_counter()
    soft = None if time_budget is None else t0 + time_budget  # the budget's end
    deadline = soft if hard_budget is None or soft is None else t0 + max(hard_budget, time_budget)
    soft = soft if soft is not None and soft < deadline else None  # None: no soft end before the deadline
    N = build(P)
    optimal = lp_sol is not None and lp_sol.status == Status.OPTIMAL
    alpha_ref = lp_sol.alpha if optimal else np.inf
    cores = workers or os.cpu_count() or 1
    if factors is None:
        cfg = settings.of(P)
        factors = (cfg.large_start_factors_very_large if _very_large(P) else
                   cfg.large_start_factors_one_round_3d if _one_round(P) and P.scene.dim == 3 else
                   cfg.large_start_factors)
    if optimal:  # (label, friction factor): each start's LP is solved by the start itself
        if _one_round(P):
            factors = tuple(factors)[:max(1, cores)]
        plan = [(start_label(float(f)), float(f)) for f in factors]
    else:
        plan = starts(P, lp_sol, factors)
    if not plan:
        return RouteOutcome(False, N=N, reason="no start: the dead load alone has no equilibrium",
                            time_s=time.perf_counter() - t0, workers=0)
    workers = min(len(plan), cores)
    log.info("step 2, large-scale route: %d start(s) (%s) on %d process(es)", len(plan),
             ", ".join(label for label, _ in plan), workers)
    grace = _very_large(P)  # the starts stop large_grace after the first verified one (2D, very large)
    shared = grace or soft is not None  # the starts stop each other
    soft = None if grace else soft
    runs, best = [], None
    procs = workers
    for opts, suffix, what in _rounds(P):
        if best is not None or (deadline is not None and time.perf_counter() > deadline):
            break
        if suffix:
            log.info("step 2, large-scale route: no start verified; the starts again, %s", what)
        t_round = time.perf_counter() if suffix else t0  # the shared stop's origin
        workers, results = _round(P, lp_sol, plan, alpha_ref, deadline, N, procs,
                                  t_round if shared else None, soft, opts)
        for (label, _), r in zip(plan, results):
            runs.append({"start": label + suffix, **{k: v for k, v in r.items() if k != "z"}})
            log.info("step 2, large-scale route, start %s: %s (%.1f s)", label + suffix,
                     f"alpha {r['alpha']:.6g}, verified" if r["verified"] else r.get("reason", "not verified"),
                     r.get("time_s") or 0.0)
            if r["verified"] and (best is None or r["alpha"] < best[0]):
                best = (r["alpha"], r["z"], label + suffix)
    if best is None:
        return RouteOutcome(False, N=N, starts=runs, time_s=time.perf_counter() - t0, workers=workers,
                            reason="no start reached a verified point: "
                            + "; ".join(f"{r['start']}: {r.get('reason')}" for r in runs))
    ok, res, why = nlp.check(N, best[1], alpha_ref)
    verified = [r["alpha"] for r in runs if r.get("verified")]
    return RouteOutcome(ok, best[0], best[1], N, why, starts=runs, time_s=time.perf_counter() - t0,
                        residuals=res, start=best[2], alpha_best=min(verified), alpha_worst=max(verified),
                        n_verified=len(verified), workers=workers)
