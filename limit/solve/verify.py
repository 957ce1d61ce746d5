"""A posteriori checks of a limit-analysis answer, independent of the solver's status.

All residuals are measured on the scaled problem (forces in units of the mean
block weight Wc, moments in Wc Lc, mechanism normalised to unit live-load
work), so the tolerances below are dimensionless. Their values are the settings in use
(:mod:`limit.settings`: ``tol_eq``, ``tol_yield``, ``tol_kin``, ``tol_gap``, ``tol_comp``
of the problem's options); the module names TOL_* are the defaults:

* equilibrium  ``|E x + f0 + alpha fL|_inf``            <= TOL_EQ, and per block:
  its out-of-balance force over the size of its own load (the norm of its
  dead plus alpha times live force; moments over that load times the block's
  size), so that a light block beside a heavy one is checked on its own scale
* yield        ``max(Yh xh - kh)`` (rows of unit largest coefficient) <= TOL_YIELD
* compatibility ``|A u + Y.T lam|_inf`` (associative) or ``|A u - G lam|``
  (non-associative), relative to the largest term       <= TOL_KIN
* multipliers  ``min(lam)``                              >= -TOL_KIN
* normalisation ``|fL . u - 1|``                         <= TOL_KIN
* duality gap  ``|alpha - (-f0 . u + k . lam)| / max(1, |alpha|)`` <= TOL_GAP
  (associative); for a frictional point instead the complementarity
  ``sum |lam s| / max(1, |alpha|)`` <= TOL_COMP and alpha not above the LP's
  (relative to max(1, alpha_LP)) by more than TOL_GAP.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from limit.settings import DEFAULT, Settings, of

#: the default tolerances (the check reads those of the settings in use: :func:`limits`)
TOL_EQ = DEFAULT.tol_eq
TOL_YIELD = DEFAULT.tol_yield
TOL_KIN = DEFAULT.tol_kin
TOL_GAP = DEFAULT.tol_gap
TOL_COMP = DEFAULT.tol_comp


def limits(s: Settings = DEFAULT) -> dict:
    """The limits every answer meets (the associative LP's and a frictional point's), by residual."""
    return {"equilibrium": s.tol_eq, "block_equilibrium": s.tol_eq, "yield": s.tol_yield,
            "compatibility": s.tol_kin, "multipliers": s.tol_kin, "normalisation": s.tol_kin}


#: the default limits
LIMITS = limits()


def _inf(v) -> float:
    v = np.asarray(v)
    return float(np.abs(v).max()) if v.size else 0.0


def block_equilibrium(P, alpha, x) -> float:
    """Largest out-of-balance of a free block relative to its own load (see module docstring)."""
    nd, d = P.scene.ndof, P.scene.dim
    res = P.full(P.A.T @ x + P.f0 + alpha * P.fL).reshape(-1, nd)
    load = P.full(P.f0 + alpha * P.fL).reshape(-1, nd)
    size = P.block_size
    f_load = np.linalg.norm(load[:, :d], axis=1) + np.linalg.norm(load[:, d:], axis=1) / size
    floor = 1e-9 * max(float(f_load.max(initial=0.0)), 1e-300)
    f_load = np.maximum(f_load, floor)
    rf = np.linalg.norm(res[:, :d], axis=1) / f_load
    rm = np.linalg.norm(res[:, d:], axis=1) / (f_load * size)
    return float(max(rf.max(initial=0.0), rm.max(initial=0.0)))


def static_residuals(P, alpha, x) -> dict:
    """Equilibrium and yield residuals of interface actions x at load factor alpha."""
    xh = x / P.Dx
    eq = P.Eh @ xh + P.f0h + alpha * P.fLh
    y = P.Yh @ xh - P.kh
    return {"equilibrium": _inf(eq), "block_equilibrium": block_equilibrium(P, alpha, x),
            "yield": float(max(y.max(), 0.0)) if y.size else 0.0}


def kinematic_residuals(P, u, lam, flow: str = "associative") -> dict:
    """Compatibility, sign and normalisation residuals of a mechanism (u, lam)."""
    vh = u * P.Df
    lamh = lam * P.Sy
    if flow == "associative":
        terms = (P.Eh.T @ vh, P.Yh.T @ lamh)
        res = terms[0] + terms[1]
    else:
        Gh = (sp.diags(P.Dx) @ P.model.G @ sp.diags(1.0 / P.Sy)).tocsr()  # flow in scaled x-space
        terms = (P.Eh.T @ vh, Gh @ lamh)
        res = terms[0] - terms[1]
    scale = max(_inf(terms[0]), _inf(terms[1]), 1.0)
    return {"compatibility": _inf(res) / scale, "multipliers": float(max(-lamh.min(), 0.0)) if lamh.size else 0.0,
            "normalisation": abs(float(P.fL @ u) - 1.0)}


def check_lp(P, sol) -> tuple[bool, dict, str]:
    """Verify an associative LP solution with both its stresses and its mechanism.

    Returns (ok, residuals, reason). The duality gap compares the static alpha
    with the kinematic value -f0 . u of the mechanism.
    """
    if sol.alpha is None or sol.x is None or sol.u is None or sol.lam is None:
        return False, {}, "no solution to check"
    r = static_residuals(P, sol.alpha, sol.x)
    r.update(kinematic_residuals(P, sol.u, sol.lam, "associative"))
    alpha_kin = float(-P.f0 @ sol.u + P.model.k @ sol.lam)
    r["alpha_kinematic"] = alpha_kin
    r["duality_gap"] = abs(sol.alpha - alpha_kin) / max(1.0, abs(sol.alpha))
    s = of(P)
    ok, reason = judge(r, s, duality_gap=s.tol_gap)
    return ok, r, reason


def judge(r: dict, s: Settings = DEFAULT, **extra: float) -> tuple[bool, str]:
    """(ok, reason) of residuals ``r`` against the limits of settings ``s`` (:func:`limits`) and
    the ``extra`` limits (name=limit); a missing or NaN residual fails."""
    bad = [f"{k} residual {r.get(k, float('nan')):.2e} > {lim:.0e}" for k, lim in {**limits(s), **extra}.items()
           if not (r.get(k, float("nan")) <= lim)]
    return not bad, "; ".join(bad)
