"""The mechanism of a dead-load collapse: what moves when the dead load cannot be carried alone.

The dead load alone is carried unless some kinematically admissible mechanism u (associative
flow: ``A u = -Y.T lam``, ``lam >= 0``) lets it do more work than the joints dissipate,
``f0 . u - k . lam > 0`` (Farkas' lemma on the equilibrium ``E x + f0 = 0``, ``Y x <= k``; dry
joints, k = 0, dissipate nothing). This module finds one such mechanism with unit net work, the least moving (least 1-norm of the
scaled velocities), and names its blocks and joints for the "infeasible" answer.
"""
from __future__ import annotations

import numpy as np

from limit.solve import mechanism


def solve(P):
    """The mechanism u (n_dof,) of the dead load alone, normalised to ``f0 . u = 1``; None where
    the dead load is carried (no such mechanism) or the solver gives none."""
    import cvxpy as cp

    if P.n_dof == 0 or not np.any(P.f0h):
        return None
    vh = cp.Variable(P.n_dof)
    if P.model.n_faces:
        lamh = cp.Variable(P.model.n_faces, nonneg=True)
        cons = [P.f0h @ vh - P.kh @ lamh == 1, P.Eh.T @ vh + P.Yh.T @ lamh == 0]
    else:
        cons = [P.f0h @ vh == 1]
    prob = cp.Problem(cp.Minimize(cp.norm1(vh)), cons)
    try:
        prob.solve(solver=cp.CLARABEL)
    except cp.SolverError:
        return None
    if prob.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or vh.value is None:
        return None
    u = np.asarray(vh.value, dtype=float) / P.Df
    return u / float(P.f0 @ u)


def describe(P, u, moving: float = 1e-6) -> dict:
    """The result part of a dead-load mechanism: ``blocks`` (ids of the free blocks that move:
    velocity above ``moving`` times the largest), ``joints`` (``{"blocks": [a, b], "modes":
    [...]}``, modes among rock, slide, twist, open), ``mechanism`` (per free block, as the
    result file's) and the ``interfaces`` flags (indices) that :mod:`reports.plots` draws."""
    per = mechanism.per_block(P, u)
    free = [P.scene.blocks[i] for i in P.scene.free]
    size = np.ptp(np.vstack([b.poly.vertices for b in free]), axis=0).max() if free else 1.0
    d = P.scene.dim
    speed = {bid: float(np.linalg.norm(v[:d]) + np.linalg.norm(v[d:]) * size) for bid, v in per.items()}
    top = max(speed.values(), default=0.0)
    blocks = [bid for bid, s in speed.items() if top > 0 and s > moving * top]
    cls = mechanism.classify(P, u)
    pairs = P.I.pairs(P.scene)
    joints = []
    for k, (a, b) in enumerate(pairs):
        modes = [m for m in ("rock", "slide", "twist", "open") if cls[m][k]]
        if modes:
            joints.append({"blocks": [a, b], "modes": modes})
    return {"blocks": blocks, "joints": joints, "mechanism": per,
            "normalisation": "unit work of the dead load: f0 . u = 1",
            "interfaces": {k: np.flatnonzero(v).tolist() for k, v in cls.items()}}


def phrase(part: dict, limit: int = 6) -> str:
    """One line naming the blocks and joints of a :func:`describe` part."""
    def shown(items):
        return ", ".join(items[:limit]) + (f" and {len(items) - limit} more" if len(items) > limit else "")

    blocks = shown([f"'{b}'" for b in part["blocks"]])
    joints = shown([f"{j['blocks'][0]}|{j['blocks'][1]} ({'+'.join(j['modes'])})" for j in part["joints"]])
    return (f"dead-load mechanism: block{'s' if len(part['blocks']) > 1 else ''} {blocks} move"
            + ("s" if len(part["blocks"]) == 1 else "")
            + (f"; joints {joints}" if joints else "; no joint holds them"))
