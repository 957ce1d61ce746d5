"""Extrapolation of the DEM load factor to rigid contacts.

A penalty contact penetrates, so a block rocks about a toe that sits inside
its face: alpha found at settlement strain eps falls short of the rigid-block
value. For a block on an elastic (Winkler) foundation the shortfall is
c eps^(1/3) to first order; sliding collapses do not depend on eps. Model:
alpha(eps) = alpha_rigid - c eps^p (p = 1/3 by default), fitted to the runs
(exactly through two, least squares through more): Richardson extrapolation.
"""
from __future__ import annotations

import numpy as np


def richardson(eps, alpha, halfwidth=None, p=1.0 / 3.0) -> dict:
    """Fit alpha = alpha_rigid - c eps^p.

    ``eps``, ``alpha``: the runs (at least one; with one the "extrapolation" is the
    raw value). ``halfwidth``: half the bisection bracket of each alpha; it is
    carried through the (linear) fit as a worst-case bound ``uncertainty``.
    Returns {alpha_rigid, coefficient c, exponent p, uncertainty, correction
    (alpha_rigid minus the stiffest run's alpha)}.
    """
    e = np.asarray(eps, dtype=float)
    a = np.asarray(alpha, dtype=float)
    h = np.zeros_like(a) if halfwidth is None else np.asarray(halfwidth, dtype=float)
    if e.size == 0 or e.size != a.size or e.size != h.size:
        raise ValueError("richardson: need one alpha (and half-width) per eps")
    stiffest = int(np.argmin(e))
    if e.size == 1:
        return {"alpha_rigid": float(a[0]), "coefficient": 0.0, "exponent": p,
                "uncertainty": float(h[0]), "correction": 0.0}
    x = e ** p
    A = np.column_stack([np.ones_like(x), -x])
    # weights of the least-squares solution: [alpha_rigid, c] = W @ alpha
    W = np.linalg.pinv(A)
    ar, c = W @ a
    return {"alpha_rigid": float(ar), "coefficient": float(c), "exponent": p,
            "uncertainty": float(np.abs(W[0]) @ h), "correction": float(ar - a[stiffest])}
