"""Global minimum of the frictional problem for small scenes, as a mixed-integer LP.

The NLP of :mod:`limit.solve.nlp_problem` is linear but for the complementarity
``lam_j s_j = 0`` of every yield face j. With one binary y_j per face
(y_j = 1: the face may flow and its slack is zero; y_j = 0: it holds and its
multiplier is zero) and bounds

    lam_j <= L_j y_j,     s_j <= S_j (1 - y_j),

the problem becomes a MILP whose optimum is the global minimum of alpha
(scipy.optimize.milp, HiGHS branch and cut). Two things make it solvable:

* tight bounds: S_j is the largest slack of face j over all statically
  admissible stresses with 0 <= alpha <= alpha_ub, L_j the largest multiplier
  over all mechanisms whose dead-load work is at most alpha_ub (one small LP
  each); alpha_ub is the best value known (the NLP's, else the LP's);
* the valid inequality ``alpha >= -f0 . u``: by the work equation
  alpha = -f0 . u + (dissipation >= 0) at every complementary point (friction, and the
  cohesion and tension of bonded joints, dissipate).

Unbounded L_j (faces free to slide at zero normal force) are capped and the
cap is enlarged until no multiplier reaches it. Practical up to some 30 blocks.
"""
from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.optimize import Bounds, LinearConstraint, milp

from limit.solve import lpsub
from limit.solve.nlp_problem import build
from limit.solve.status import GlobalStatus

log = logging.getLogger(__name__)

#: seconds between the progress lines of the bound tightening
PROGRESS_EVERY_S = 30.0


def _bounds(N, P, alpha_ub, deadline):
    """Per-face slack bounds S and multiplier bounds L (inf where unbounded): one LP per face and
    bound, each family sharing its constraints in one HiGHS model that starts from the last
    solve's basis (:class:`limit.solve.lpsub.HighsLP`)."""
    nf = P.model.n_faces
    lo, hi = N.bounds()
    lo[N.ia], hi[N.ia] = 0.0, alpha_ub
    ndof = P.n_dof
    S = np.full(nf, np.inf)
    L = np.full(nf, np.inf)
    t0 = last = time.perf_counter()

    def tell(done: int) -> None:
        nonlocal last
        now = time.perf_counter()
        if now > deadline:
            raise TimeoutError
        if now - last >= PROGRESS_EVERY_S:
            last = now
            log.info("global MILP: bounds, %d of %d LPs (%.0f s)", done, 2 * nf, now - t0)

    log.info("global MILP: bounds of %d yield faces' slacks and multipliers, %d LPs", nf, 2 * nf)
    statics = lpsub.HighsLP(N.Aeq[:ndof], N.beq[:ndof], N.Yx, N.kh, lo, hi)
    for j in range(nf):  # s_j = kh_j - Yx_j z at its largest: Yx_j z at its least
        tell(j)
        r = statics.solve(N.Yx[j].toarray().ravel())
        if r.ok:
            S[j] = max(N.kh[j] - r.fun, 0.0)
    work = sp.hstack([sp.csr_matrix((1, 1 + P.model.n_x)), sp.csr_matrix(-P.f0h.reshape(1, -1)),
                      sp.csr_matrix((1, nf))]).tocsr()
    kinematics = lpsub.HighsLP(N.Aeq[ndof:], N.beq[ndof:], work, np.array([alpha_ub]), lo, hi)
    for j in range(nf):
        tell(nf + j)
        c = np.zeros(N.n)
        c[N.sl.start + j] = -1.0
        r = kinematics.solve(c)
        if r.ok:
            L[j] = max(-r.fun, 0.0)
    return S, L


@dataclass(frozen=True)
class GlobalMinimum:
    """The outcome of :func:`global_minimum`. ``status``: :class:`GlobalStatus`; ``alpha``: the
    best point's load factor (None without a point); ``bound``: the proven lower bound of alpha
    (None where the search did not give one); ``time_s``: seconds; ``reason``: why it is not a
    proven optimum (empty where it is); ``z``: the best point, unknowns of the scaled NLP
    (:func:`limit.solve.nlp_problem.build`; None without a point)."""

    status: GlobalStatus
    alpha: float | None = None
    bound: float | None = None
    time_s: float = 0.0
    reason: str = ""
    z: np.ndarray | None = field(default=None, repr=False)

    def entry(self) -> dict:
        """The result file's ``nlp.global`` entry (docs/formats.md): status, alpha, bound, time_s, reason."""
        return {"status": self.status, "alpha": self.alpha, "bound": self.bound, "time_s": self.time_s,
                "reason": self.reason}


def global_minimum(P, alpha_ub: float, time_limit: float = 120.0, max_enlarge: int = 4) -> GlobalMinimum:
    """The global minimum of alpha by the complementarity MILP (:class:`GlobalMinimum`).

    ``alpha_ub``: a known feasible value (NLP) or the LP's alpha. "optimal" means
    proven global optimum (relative gap 1e-7); "time_limit" returns the best
    point found (``alpha``, may be None) and the proven lower bound (``bound``).
    """
    t0 = time.perf_counter()
    deadline = t0 + time_limit
    N = build(P)
    nf = P.model.n_faces
    n = N.n
    try:
        S, L = _bounds(N, P, alpha_ub * (1 + 1e-9) + 1e-12, deadline)
    except TimeoutError:
        return GlobalMinimum(GlobalStatus.TIME_LIMIT, time_s=time.perf_counter() - t0,
                             reason=f"bound tightening not finished within {time_limit:g} s")
    finite = L[np.isfinite(L)]
    cap = 10.0 * max(float(finite.max()) if finite.size else 1.0, 1.0)
    lo, hi = N.bounds()
    lo[N.ia], hi[N.ia] = 0.0, alpha_ub * (1 + 1e-9) + 1e-12
    c = np.zeros(n + nf)
    c[N.ia] = 1.0
    integrality = np.concatenate([np.zeros(n), np.ones(nf)])
    lam_cols = np.arange(N.sl.start, N.sl.stop)
    sel = sp.csr_matrix((np.ones(nf), (np.arange(nf), lam_cols)), shape=(nf, n))
    cut = sp.csr_matrix(np.concatenate([[-1.0], np.zeros(P.model.n_x), -P.f0h, np.zeros(nf), np.zeros(nf)]))
    out = None
    for _ in range(max_enlarge + 1):
        Lc = np.where(np.isfinite(L), L, cap)
        Sc = np.where(np.isfinite(S), S, 10.0 * max(float(S[np.isfinite(S)].max(initial=1.0)), 1.0))
        A = sp.vstack([
            sp.hstack([N.Aeq, sp.csr_matrix((N.Aeq.shape[0], nf))]),
            sp.hstack([N.Yx, sp.csr_matrix((nf, nf))]),
            sp.hstack([sel, -sp.diags(Lc)]),
            sp.hstack([-N.Yx, sp.diags(Sc)]),
            cut,
        ]).tocsr()
        lb = np.concatenate([N.beq, np.full(3 * nf, -np.inf), [-np.inf]])
        ub = np.concatenate([N.beq, N.kh, np.zeros(nf), Sc - N.kh, [0.0]])
        bl = np.concatenate([lo, np.zeros(nf)])
        bu = np.concatenate([hi, np.ones(nf)])
        left = deadline - time.perf_counter()
        if left <= 0:
            break
        log.info("global MILP: branch and cut on %d binaries, alpha <= %.6g, %.0f s left", nf, alpha_ub, left)
        res = milp(c, integrality=integrality, bounds=Bounds(bl, bu), constraints=LinearConstraint(A, lb, ub),
                   options={"time_limit": left, "mip_rel_gap": 1e-7})
        bound = getattr(res, "mip_dual_bound", None)
        log.info("global MILP: %s, alpha %s, bound %s (%.0f s)",
                 {0: "optimal", 1: "time limit", 2: "infeasible", 3: "unbounded"}.get(res.status, "failed"),
                 "-" if res.x is None else f"{res.x[N.ia]:.6g}", "-" if bound is None else f"{bound:.6g}",
                 time.perf_counter() - t0)
        if res.x is None:
            status = {1: GlobalStatus.TIME_LIMIT, 2: GlobalStatus.INFEASIBLE,
                      3: GlobalStatus.UNBOUNDED}.get(res.status, GlobalStatus.FAILED)
            return GlobalMinimum(status, None, bound, time.perf_counter() - t0, res.message)
        z = res.x[:n]
        out = GlobalMinimum(GlobalStatus.OPTIMAL if res.status == 0 else GlobalStatus.TIME_LIMIT, float(z[N.ia]),
                            bound, time.perf_counter() - t0, "" if res.status == 0 else res.message, z)
        capped = (~np.isfinite(L)) & (z[N.sl] > 0.5 * cap)
        if not capped.any():
            return out
        cap *= 10.0  # a capped multiplier came close to its cap: it might cut off the optimum
    if out is None:  # the time ran out before the first search
        return GlobalMinimum(GlobalStatus.TIME_LIMIT, time_s=time.perf_counter() - t0,
                             reason="multiplier cap still active")
    return GlobalMinimum(out.status, out.alpha, out.bound, time.perf_counter() - t0, out.reason, out.z)
