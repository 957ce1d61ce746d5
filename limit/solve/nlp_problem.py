"""The non-associative (frictional) collapse problem of Baggio & Trovalusci, eqs. (7)-(10).

Unknowns (all kept, none eliminated; scaled as in :mod:`limit.model.assemble`),
stacked into one vector ``z = [alpha, xh, vh, lamh]``:

* alpha — the load factor;
* xh (n_x) — interface actions (statics);
* vh (n_dof) — block velocities (the mechanism), kept explicitly instead of
  the paper's elimination through a maximal-rank submatrix, so that every
  constraint stays sparse;
* lamh (n_faces) — plastic multipliers of the yield faces, >= 0.

Constraints::

    equilibrium      Eh xh + alpha fLh = -f0h
    yield            s(xh) = kh - Yh xh >= 0   (kh = 0 for dry joints)
    flow (no dilatancy)  Eh.T vh - Gh lamh = 0
    normalisation    fLh . vh = 1
    complementarity  c(z) = lamh . s(xh) = 0
    bounds           lamh >= 0

and the objective is ``min alpha``. Everything is linear except the bilinear
complementarity, whose gradient is ``dc/dxh = -Yh.T lamh``, ``dc/dlamh = s``
and whose Hessian is constant. ``c`` is in units of alpha (work of the
interface actions per unit work of the live load).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass
class NLPProblem:
    P: object
    Gh: sp.csr_matrix      # (n_x, n_f) scaled non-associative flow
    Aeq: sp.csr_matrix     # (n_dof + n_x + 1, n) equality constraints
    beq: np.ndarray
    Yx: sp.csr_matrix      # (n_f, n) yield rows on z: s = kh - Yx z, ``Yx z <= kh``
    n: int
    ia: int
    sx: slice
    sv: slice
    sl: slice

    def split(self, z):
        return z[self.ia], z[self.sx], z[self.sv], z[self.sl]

    def join(self, alpha, xh, vh, lamh):
        z = np.empty(self.n)
        z[self.ia], z[self.sx], z[self.sv], z[self.sl] = alpha, xh, vh, lamh
        return z

    @property
    def kh(self) -> np.ndarray:
        """(n_f,) the yield rows' right-hand side, ``Yx z <= kh``."""
        return self.P.kh

    def slack(self, z):
        return self.P.kh - self.P.Yh @ z[self.sx]

    def comp(self, z) -> float:
        return float(z[self.sl] @ self.slack(z))

    def comp_grad(self, z, clip: bool = False) -> np.ndarray:
        """Gradient of c(z); ``clip``: evaluated with lamh and s clipped at 0 (never a negative cost)."""
        lam, s = z[self.sl], self.slack(z)
        if clip:
            lam, s = np.maximum(lam, 0.0), np.maximum(s, 0.0)
        g = np.zeros(self.n)
        g[self.sx] = -(self.P.Yh.T @ lam)
        g[self.sl] = s
        return g

    def bounds(self):
        """(lower, upper) arrays: alpha and lamh >= 0 where required, others free."""
        lo = np.full(self.n, -np.inf)
        hi = np.full(self.n, np.inf)
        lo[self.sl] = 0.0
        return lo, hi

    # unscaled views
    def unscale(self, z):
        P = self.P
        a, xh, vh, lh = self.split(z)
        return float(a), P.Dx * xh, vh / P.Df, lh / P.Sy

    def scale(self, alpha, x, u, lam):
        P = self.P
        return self.join(alpha, x / P.Dx, u * P.Df, lam * P.Sy)


def build(P) -> NLPProblem:
    """The NLP of the assembled problem P (:class:`limit.model.assemble.Assembled`)."""
    nx, nv, nf = P.model.n_x, P.n_dof, P.model.n_faces
    n = 1 + nx + nv + nf
    ia, sx, sv, sl = 0, slice(1, 1 + nx), slice(1 + nx, 1 + nx + nv), slice(1 + nx + nv, n)
    Gh = (sp.diags(P.Dx) @ P.model.G @ sp.diags(1.0 / P.Sy)).tocsr()
    Z = lambda r, c: sp.csr_matrix((r, c))
    col = lambda v: sp.csr_matrix(np.asarray(v).reshape(-1, 1))
    eq_rows = sp.hstack([col(P.fLh), P.Eh, Z(nv, nv), Z(nv, nf)])
    flow_rows = sp.hstack([Z(nx, 1), Z(nx, nx), P.Eh.T, -Gh])
    norm_row = sp.hstack([Z(1, 1), Z(1, nx), sp.csr_matrix(P.fLh.reshape(1, -1)), Z(1, nf)])
    Aeq = sp.vstack([eq_rows, flow_rows, norm_row]).tocsr()
    beq = np.concatenate([-P.f0h, np.zeros(nx), [1.0]])
    Yx = sp.hstack([Z(nf, 1), P.Yh, Z(nf, nv), Z(nf, nf)]).tocsr()
    return NLPProblem(P, Gh, Aeq, beq, Yx, n, ia, sx, sv, sl)
