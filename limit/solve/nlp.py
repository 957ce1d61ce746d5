"""Step 2: the non-associative frictional collapse factor, started from the LP (step 1).

Problem: :mod:`limit.solve.nlp_problem` (the paper's eqs. 7-10, unknowns alpha,
interface actions, block velocities and plastic multipliers). Solvers:

``slsqp`` (small problems, up to the setting ``slsqp_max_vars`` unknowns)
    scipy's SLSQP, the SQP method of the paper, on ``min alpha`` with the
    linear constraints and the complementarity ``lam . s = 0`` as an equality,
    every gradient analytic (constant for the linear constraints).
``sla`` (any size)
    a successive linearisation (sequential LP) of the exact-penalty problem
    ``min alpha + rho lam . s`` over the polyhedron of the linear constraints:
    each step solves one sparse LP for the direction (the linearised penalty,
    analytic gradient), then an exact line search on the quadratic penalty;
    rho grows tenfold until complementarity holds (Mangasarian's successive
    linearisation algorithm for bilinear programs, which stops at a
    stationary point). It replaces trust-constr, which on these problems is
    both slower and less reliable (see bench/nlp_bench.py).

Both start from the LP solution (the starts: :mod:`limit.solve.nlp_starts`) made
compatible with the non-associative flow (phase 1: the LP stresses fixed, the mechanism re-solved to minimise the
complementarity gap). The end point is polished by the *piece LP*: with each
yield face assigned to "flows" (lam > 0 allowed, s = 0 imposed) or "holds"
(lam = 0) as at the end point, the problem is an LP whose optimum is exactly
complementary. The final point is then checked independently
(:func:`check`): a result that fails is reported as "failed", never as a number.
"""
from __future__ import annotations

import time

import numpy as np
import scipy.sparse as sp
from scipy.optimize import minimize

from limit import settings
from limit.solve import lpsub, mechanism, verify
from limit.solve.nlp_problem import NLPProblem
from limit.model.yield_domain import SLIDE, TWIST



# ---------------------------------------------------------------------------
# Phase 1


def phase1(N: NLPProblem, z0: np.ndarray, backend: str, face_cost: np.ndarray | None = None
           ) -> tuple[np.ndarray | None, str]:
    """Keep alpha and the stresses of z0, find a non-associative mechanism minimising lam . s
    (``face_cost`` (n_faces,) >= 0: lam . face_cost instead).

    Only the kinematic unknowns (vh, lamh) are solved for: the flow rule
    ``Eh.T vh - Gh lamh = 0``, ``fLh . vh = 1``, ``lamh >= 0``. The statics of z0 are
    taken as they are (an interior-point LP answer meets equilibrium and yield only to
    its tolerance; imposing them again as constraints on fixed values made HiGHS
    report a solve error on a 3D wall).
    """
    P = N.P
    nv, nf = P.n_dof, P.model.n_faces
    A = sp.vstack([sp.hstack([P.Eh.T, -N.Gh]),
                   sp.hstack([sp.csr_matrix(P.fLh.reshape(1, -1)), sp.csr_matrix((1, nf))])]).tocsr()
    b = np.zeros(A.shape[0])
    b[-1] = 1.0
    c = np.concatenate([np.zeros(nv), np.maximum(N.slack(z0), 0.0) if face_cost is None else face_cost])
    lo = np.concatenate([np.full(nv, -np.inf), np.zeros(nf)])
    hi = np.full(nv + nf, np.inf)
    res = lpsub.solve(c, A, b, sp.csr_matrix((0, nv + nf)), np.zeros(0), lo, hi, backend)
    if not res.ok:
        return None, f"phase 1 LP: {res.status}"
    z = z0.copy()
    z[N.sv], z[N.sl] = res.z[:nv], res.z[nv:]
    return z, ""


# ---------------------------------------------------------------------------
# Solvers


def solve_slsqp(N: NLPProblem, z0: np.ndarray, maxiter: int = 100, tol: float = 1e-10) -> tuple[np.ndarray, str]:
    """SLSQP on min alpha s.t. linear constraints and lam . s = 0 (analytic gradients)."""
    Aeq = N.Aeq.toarray()
    Yx = N.Yx.toarray()
    e = np.zeros(N.n)
    e[N.ia] = 1.0
    lo, hi = N.bounds()
    lo[N.ia] = 0.0
    cons = [
        {"type": "eq", "fun": lambda z: Aeq @ z - N.beq, "jac": lambda z: Aeq},
        {"type": "ineq", "fun": lambda z: N.kh - Yx @ z, "jac": lambda z: -Yx},
        {"type": "eq", "fun": lambda z: np.array([N.comp(z)]), "jac": lambda z: N.comp_grad(z)[None, :]},
    ]
    bounds = list(zip(np.where(np.isfinite(lo), lo, None), np.where(np.isfinite(hi), hi, None)))
    res = minimize(lambda z: z[N.ia], z0, jac=lambda z: e, method="SLSQP", constraints=cons, bounds=bounds,
                   options={"maxiter": maxiter, "ftol": tol})
    return res.x, f"SLSQP: {res.message} ({res.nit} iterations)"


def solve_sla(N: NLPProblem, z0: np.ndarray, backend: str = "highs", rho0: float = 1.0, rho_max: float = 1e6,
              maxit: int = 200, lp=None, jitter: np.ndarray | None = None,
              deadline: float | None = None) -> tuple[np.ndarray, str]:
    """Successive linearisation of min alpha + rho lam . s over the linear constraints.

    ``lp``: an :class:`limit.solve.lpsub.HighsLP` of the constraint polyhedron to reuse
    (warm starts across steps and runs); built here for the "highs" backend if not given.
    ``jitter`` (n_faces,) >= 0: extra cost per unit multiplier, rho * jitter . lam, which
    steers a restart towards other mechanisms (the final point is re-checked without it).
    ``deadline`` (time.perf_counter() value): stop there with the point reached. The penalty
    stops growing once lam . s <= the setting ``sla_comp_target`` x max(1, alpha) (a stopping
    target below the check's ``tol_comp``, so that the point passes the check).
    """
    target = settings.of(N.P).sla_comp_target
    z = z0.copy()
    lo, hi = N.bounds()
    lo[N.ia] = 0.0
    e = np.zeros(N.n)
    e[N.ia] = 1.0
    bub = N.kh
    if lp is None and backend == "highs":
        lp = lpsub.HighsLP(N.Aeq, N.beq, N.Yx, bub, lo, hi)
    rho = rho0
    iters = 0
    while True:
        for _ in range(maxit):
            if deadline is not None and time.perf_counter() > deadline:
                return z, f"SLA: time budget spent after {iters} LPs (penalty {rho:g})"
            iters += 1
            # the gradient of lam . s at the point clipped to lam, s >= 0: a slack a rounding error
            # below zero would put a negative cost on that face's multiplier, and a mechanism
            # doing no live-load work along it makes the direction LP unbounded (seen on
            # 300-block walls with HiGHS)
            g = e + rho * N.comp_grad(z, clip=True)
            if jitter is not None:
                g[N.sl] += rho * jitter
            res = lp.solve(g) if lp is not None else lpsub.solve(g, N.Aeq, N.beq, N.Yx, bub, lo, hi, backend)
            if not res.ok:
                return z, f"SLA: direction LP failed ({res.status}) after {iters} LPs"
            d = res.z - z
            slope = float(g @ d)
            f = z[N.ia] + rho * N.comp(z)
            if slope >= -1e-10 * (1.0 + abs(f)):
                break
            ds = -(N.P.Yh @ d[N.sx])
            curv = rho * float(d[N.sl] @ ds)
            t = 1.0 if curv <= 0 else min(1.0, -slope / (2.0 * curv))
            z = z + t * d
        if N.comp(z) <= target * max(1.0, z[N.ia]) or rho >= rho_max:
            break
        rho *= 10.0
    return z, f"SLA: {iters} LPs, final penalty {rho:g}"


def flowing_faces(N: NLPProblem, z: np.ndarray, rule: str = "ratio") -> np.ndarray:
    """(n_faces,) bool: the faces taken as flowing at z. "ratio": lam_j / max lam > s_j / max s;
    "support": lam_j > 1e-9 max lam (every face the mechanism uses)."""
    lam = np.maximum(z[N.sl], 0.0)
    s = np.maximum(N.slack(z), 0.0)
    lmax = max(lam.max(initial=0.0), 1e-300)
    if rule == "ratio":
        return lam / lmax > s / max(s.max(initial=0.0), 1e-300)
    return lam > 1e-9 * lmax


def polish(N: NLPProblem, z: np.ndarray, backend: str, rule: str = "ratio") -> tuple[np.ndarray | None, str]:
    """The piece LP: faces that flow at z keep s = 0, the others lam = 0; min alpha exactly complementary.

    ``rule`` picks the flowing faces: "ratio" (lam_j / max lam > s_j / max s) or
    "support" (lam_j > 1e-9 max lam: every face the mechanism uses).
    """
    flows = flowing_faces(N, z, rule)
    lo, hi = N.bounds()
    lo[N.ia] = 0.0
    hi[N.sl.start + np.flatnonzero(~flows)] = 0.0  # lam_j = 0 where the face holds
    act = np.flatnonzero(flows)
    keep = np.flatnonzero(~flows)
    # s_j = 0 where the face flows: Yh x = kh as equalities; s >= 0 elsewhere.
    Aeq = sp.vstack([N.Aeq, N.Yx[act]]).tocsr()
    beq = np.concatenate([N.beq, N.kh[act]])
    c = np.zeros(N.n)
    c[N.ia] = 1.0
    res = lpsub.solve(c, Aeq, beq, N.Yx[keep], N.kh[keep], lo, hi, backend)
    if not res.ok:
        return None, f"piece LP ({rule}): {res.status}"
    return res.z, f"piece LP ({rule}) with {act.size} flowing faces"


# ---------------------------------------------------------------------------
# Independent check


def check(N: NLPProblem, z: np.ndarray, alpha_lp: float | None) -> tuple[bool, dict, str]:
    """Residuals of a final NLP point, unscaled and measured independently of the solver."""
    P = N.P
    alpha, x, u, lam = N.unscale(z)
    r = verify.static_residuals(P, alpha, x)
    r.update(verify.kinematic_residuals(P, u, lam, "nonassociative"))
    lamh, s = z[N.sl], N.slack(z)
    r["complementarity"] = float(np.sum(np.abs(lamh * s))) / max(1.0, abs(alpha))
    r["alpha_above_lp"] = max(0.0, alpha - alpha_lp) / max(1.0, abs(alpha_lp)) if alpha_lp is not None else 0.0
    st = settings.of(P)
    ok, reason = verify.judge(r, st, complementarity=st.tol_comp, alpha_above_lp=st.tol_gap)
    return ok, r, reason


# ---------------------------------------------------------------------------
# Step 2


def needs_nlp(P, lp_sol) -> tuple[bool, str]:
    """Whether step 2 is needed after the LP: only if an interface slides or twists in its
    mechanism. Otherwise the LP's mechanism needs no dilatancy, so the LP's point is also a
    frictional collapse state (:mod:`limit.step2` checks it as one before it skips). That makes
    it an upper bound of the frictional minimum, like every step-2 alpha, not the minimum itself:
    and a lower one exists on the catalog's 3D out-of-plane wall (27 blocks): the MILP
    (:mod:`limit.solve.milp`, stopped at 400 s without a proof) found frictional collapse states
    that pass :func:`check`, down to 0.181726 (4 interfaces slide, 2 twist, 5 rock; ``limit solve
    --global --global-time-limit 400``, which then reports it; docs/performance.md), 4.6 % below
    the LP's t/H = 0.190476, which the skip reports; step 2 run anyway stays at 0.190476 too, and YADE (0.1903) and LMGC90 (0.1914)
    follow t/H. Elsewhere the MILP's global minimum (and step 2 run anyway) agreed with the LP to
    1e-8: the catalog's other 10 such scenes and 56 generated ones (34 slender running-bond walls,
    18 portals, 4 arches). Step 2 from a state at reduced friction (the setting ``friction_starts``,
    :mod:`limit.analysis`) reaches the wall's 0.181726 without the MILP."""
    cls = mechanism.classify(P, lp_sol.u)
    n_slide, n_twist = int(cls["slide"].sum()), int(cls["twist"].sum())
    # The multipliers say the same: no sliding or twisting face flows.
    kinds = P.model.kind
    lam = np.asarray(lp_sol.lam)
    ref = max(float(lam.max(initial=0.0)), 1e-300)
    flowing = (kinds == SLIDE) | (kinds == TWIST)
    lam_flow = bool(np.any(lam[flowing] > mechanism.ACTIVE * ref))
    if n_slide == 0 and n_twist == 0 and not lam_flow:
        return False, ("no interface slides or twists in the LP mechanism: the LP's point is also a "
                       "frictional (non-dilatant) collapse state, taken as step 2's answer; a lower one can "
                       "exist (method 'nlp' searches, and the global check proves it on small scenes)")
    return True, f"{n_slide} interface(s) slide and {n_twist} twist in the LP mechanism"


def finish(N, z, alpha_lp, backend, polisher=None, unpolished: bool = True, rules=("ratio", "support"),
           first: bool = False):
    """Polish z with the piece LP when that helps, then check it: (z, ok, residuals, reason, note).
    ``polisher(N, z, backend=, rule=)``: :func:`polish` by default; ``unpolished``: z itself is
    a candidate too (after the polished points, lowest alpha first). ``rules``: the flowing-face
    rules tried; ``first``: stop at the first polished point that passes the check (one piece
    LP instead of two when it does), else the lowest alpha of all that pass."""
    cands = []
    for rule in rules:
        zp, note = (polisher or polish)(N, z, backend=backend, rule=rule)
        if zp is not None:
            if first:
                ok, res, _ = check(N, zp, alpha_lp)
                if ok:
                    return zp, True, res, "", note
            cands.append((zp, note))
    cands.sort(key=lambda c: c[0][N.ia])
    if unpolished:
        cands.append((z, "unpolished"))
    if not cands:
        return None, False, {}, "no piece LP solved", ""
    best = None
    for zc, nt in cands:
        ok, res, why = check(N, zc, alpha_lp)
        if ok:
            return zc, True, res, "", nt
        if best is None:
            best = (zc, False, res, why, nt)
    return best
