"""The ``lp`` part of the result file and the interface part shared with step 2's
(docs/formats.md, 'Result file')."""
from __future__ import annotations

import numpy as np

from limit.solve import mechanism
from limit.model.assemble import Assembled
from limit.model.dims import STRESS_NAMES
from limit.solve.status import Status


def lp_result(P: Assembled, sol, attempts, residuals, t_total: float) -> dict:
    """The ``lp`` part of the result file."""
    t = dict(P.timings)
    t.update({k: v for k, v in sol.timings.items()})
    out = {"status": sol.status, "alpha": sol.alpha if sol.status == Status.OPTIMAL else None,
           "time_s": t_total, "solver": sol.solver, "timings": t, "attempts": attempts,
           "model": {"interfaces": P.options.model, "n_slide": P.options.n_slide,
                     "slide_fit": P.options.slide_fit}}
    if sol.reason:
        out["reason"] = sol.reason
    if sol.status == Status.INFEASIBLE and sol.alpha is not None:
        out["alpha_free"] = sol.alpha
    if sol.status == Status.OPTIMAL:
        out["verification"] = residuals
        out["mechanism"] = mechanism.per_block(P, sol.u)
        out["normalisation"] = "unit work of the live load: fL . u = 1"
        cls = mechanism.classify(P, sol.u)
        out["interfaces"] = interfaces_part(P, P.model.H @ sol.x, cls)
        out["counts"] = {k: int(v.sum()) for k, v in cls.items()}
        if P.scene.ties:
            out["ties"] = ties_part(P, sol.x, sol.u)
    return out


#: a tie yields or goes slack when its elongation or shortening exceeds this x the mechanism's
#: largest relative motion at an interface (as limit.solve.mechanism.ACTIVE)
TIE_ACTIVE = mechanism.ACTIVE


def ties_part(P, x, u) -> list:
    """[{"id", "tension" (N), "capacity" (N), "state"}] per tie of the scene at the point (x, u):
    "yields" (it stretches in the mechanism: T at its capacity), "slack" (its ends approach),
    "holds" (its length does not change)."""
    nt = len(P.scene.ties)
    T = np.asarray(x, dtype=float)[-nt:]
    stretch = -(P.A[-nt:] @ np.asarray(u, dtype=float))  # elongation rates, m per unit live-load work
    mot = mechanism.interface_motions(P, u)
    ref = max(float(np.max(np.abs(np.stack(list(mot.values()))))) if len(P.I) else 0.0,
              float(np.abs(stretch).max(initial=0.0)), 1e-300)
    out = []
    for t, tj, ej in zip(P.scene.ties, T, stretch):
        state = "yields" if ej > TIE_ACTIVE * ref else "slack" if ej < -TIE_ACTIVE * ref else "holds"
        out.append({"id": t.id, "tension": float(tj), "capacity": t.capacity, "prestress": t.prestress,
                    "elongation": float(ej), "state": state})
    return out


def interfaces_part(P, r, cls) -> dict:
    """Interface pairs, their generalised stresses (local frame) and motion flags."""
    nq = P.scene.ndof
    return {
        "pairs": [list(p) for p in P.I.pairs(P.scene)],
        "stress_components": list(STRESS_NAMES[P.scene.dim]),
        "stress": np.asarray(r).reshape(-1, nq).tolist(),
        **{k: np.flatnonzero(v).tolist() for k, v in cls.items()},
    }


def ties_line(ties: list) -> str:
    """One summary line of :func:`ties_part`'s entries."""
    return "    ties: " + ", ".join(f"{t['id']} {t['state']} at {t['tension']:.4g} N" for t in ties)

