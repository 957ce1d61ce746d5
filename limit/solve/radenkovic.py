"""The lower bound of the frictional collapse multiplier for joints with cohesion (Baggio and
Trovalusci, section 3: Drucker reinterpreted through Radenkovic's theorem, after Sacchi and Save
1968; the joints "perfectly polished and cemented together by cohesion").

The collapse load of a body whose flow rule is not associated is at least the collapse load of
the standard (associative) body whose yield domain is the plastic potential, inscribed in the true
yield domain. For a Coulomb joint without dilatancy the potential of sliding and twisting does
not depend on the normal force, so the inscribed domain is the friction-free one whose sliding
strength is the least the true domain offers over every admissible normal force:

* the normal force is N >= -ft' A with ft' = min(ft, c / mu), the tension cut-off or the
  Coulomb cone's apex, whichever comes first;
* there |V| <= mu N + c A is smallest: |V| <= (c - mu ft') A = c' A;
* rocking keeps its no-tension domain with ft' (it is associative already), and crushing its fc.

So the bound is step 1's LP on the same blocks with mu' = 0, c' = max(c - mu ft', 0) and ft'.
A dry joint (c = 0) then slides freely, and a scene held by friction alone has the trivial bound
0; that is why the bound is computed only where a joint is bonded (``Interfaces.bonded``).
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from limit.model.assemble import Assembled, assemble
from limit.solve.status import Status
from limit.solve import lp as lpmod


def potential_interfaces(I):
    """A copy of the interfaces ``I`` with the inscribed friction-free properties above:
    mu' = 0 (m,), cohesion' = max(c - mu ft', 0) (Pa), tensile' = ft' (Pa); fc kept."""
    with np.errstate(divide="ignore", invalid="ignore"):
        apex = np.where(I.mu > 0, I.cohesion / I.mu, np.inf)
    ft = np.minimum(I.tensile, apex)
    c = np.maximum(I.cohesion - I.mu * ft, 0.0)
    return dataclasses.replace(I, mu=np.zeros_like(I.mu), cohesion=c, tensile=ft)


def lower_bound(P: Assembled, solver: str = lpmod.DEFAULT_SOLVER) -> dict:
    """The ``lower_bound`` part of the result file for the assembled scene ``P``:
    ``{"method": "radenkovic", "status", "alpha", "time_s", "reason"?}``.

    ``alpha`` is the checked LP's multiplier of the friction-free potential domain (a certified
    lower bound of the frictional collapse multiplier); ``status`` is that LP's: "optimal", or
    "infeasible" (the dead load needs friction, so the bound says nothing: alpha None), or
    "unbounded"/"failed" as the LP's.
    """
    from limit.solve.checked_lp import solve_lp

    t0 = time.perf_counter()
    Q = assemble(P.scene, P.options, potential_interfaces(P.I))
    sol, _, _ = solve_lp(Q, solver)
    out = {"method": "radenkovic", "status": sol.status,
           "alpha": sol.alpha if sol.status == Status.OPTIMAL else None, "time_s": time.perf_counter() - t0}
    if sol.status == Status.INFEASIBLE:
        out["reason"] = "without friction the dead load cannot be carried: the bound is not informative"
    elif sol.reason:
        out["reason"] = sol.reason
    return out
