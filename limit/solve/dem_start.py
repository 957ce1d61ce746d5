"""Step 2 from a dynamic run's collapse state: the joints that a DEM pushover opens, slides and
twists as the flowing set of the piece LP (:func:`limit.solve.nlp.polish`).

A collapsing DEM trial ends with a displacement per free block, ``u`` (m and rad: [ux, uy, rz]
in 2D, [ux, uy, uz, rx, ry, rz] in 3D, about the block's centroid, scene axes; the ``displacement``
of a DEM result, docs/formats.md). Its relative motion at each interface, ``E^T u`` (the
compatibility of Baggio & Trovalusci, eq. 3), is split on that interface's non-associative flow
directions: ``min |G_k lam_k - (E^T u)_k|, lam_k >= 0`` (a non-negative least-squares problem per
interface, scipy.optimize.nnls; G as in eq. 9: no dilatancy). The faces whose multiplier exceeds
``tau`` times the largest one flow. The motion of a dynamic run is not a rigid mechanism: blocks
that stay also settle by the contact compliance, so every rung of :data:`TAU` is tried, from the
largest motions to the smallest. Each flowing set gives the piece LP: the faces that flow keep
their slack at 0, the others their multiplier at 0, min alpha. Its point is checked by
:func:`limit.solve.nlp.check` like any other, so a wrong guess costs a piece LP and adds no
unverified number. A lower rung's set contains a higher one's, so its piece LP has every slack of
the higher one's at 0 and more: its alpha is no lower. The rungs stop at the first verified point.

A DEM run's displacement is that of a collapse well under way (large motions, every joint of the
moving part flagged), and its piece LP is often infeasible: s = 0 on too many faces. Then each
flowing set steers a successive-LP run instead: its first mechanism is the one nearest to the set
(:func:`limit.solve.nlp.phase1`, a unit cost on the multipliers of the faces outside it), and
complementarity is reached by the penalty of :func:`limit.solve.nlp.solve_sla`.

A run of YADE's vertex model or of LMGC90 also records its contact forces per block pair at its
highest equilibrium (``held_forces``). Their normal forces start the large route's fixed-point
iteration on N (:func:`limit.solve.step2_large.run_start`): if the run's state lies near a rigid
frictional collapse state, the iteration reaches it from there.
"""
from __future__ import annotations

import time

import numpy as np
from scipy.optimize import nnls

from limit import settings
from limit.solve.status import Status
from limit.solve import nlp

#: relative multiplier thresholds of the flowing set, largest first: one piece LP each
TAU = (0.1, 0.03, 0.01, 0.003, 0.001)
#: wall-clock budget (s) of the successive LPs from the flowing sets, when no piece LP verifies
SLA_BUDGET = 60.0


def state_of(data: dict) -> dict:
    """The collapse state in a result file: a ``python -m dem_validation run`` file (its ``dem``
    part), a DEM part itself, or a catalog result with ``dem``/``lmgc`` parts (the first that has
    a displacement). {"displacement", "alpha", "source", "forces"}: ``forces`` the
    ``held_forces`` of its last run that has them (YADE's stiffest, LMGC90's finest time step:
    the contact forces per block pair at the highest equilibrium), else None. ValueError naming
    what is missing."""
    if not isinstance(data, dict):
        raise ValueError("not a result file (a JSON object)")
    parts = [data] + [data[k] for k in ("dem", "lmgc") if isinstance(data.get(k), dict)]
    for part in parts:
        disp = part.get("displacement")
        if isinstance(disp, dict) and disp:
            engine = part.get("engine") or ("lmgc90" if part is data.get("lmgc") else "yade")
            held = [r for r in part.get("runs") or [] if isinstance(r, dict) and r.get("held_forces")]
            forces = held[-1]["held_forces"] if held else None
            return {"displacement": disp, "alpha": part.get("alpha"), "source": engine, "forces": forces}
    raise ValueError("no 'displacement' (per free block) in it: give the result file of a collapsed DEM run "
                     "(python -m dem_validation run ... --json OUT.json)")


def dof_vector(P, displacement: dict) -> np.ndarray:
    """(n_dof,) the displacement of every free block in P's dof order (blocked dofs dropped);
    a free block missing from ``displacement`` does not move. ValueError for a block entry of the
    wrong length."""
    nd = P.scene.ndof
    U = np.zeros((len(P.scene.free), nd))
    for k, i in enumerate(P.scene.free):
        u = displacement.get(P.scene.blocks[i].id)
        if u is None:
            continue
        if len(u) != nd:
            raise ValueError(f"displacement of block '{P.scene.blocks[i].id}': {len(u)} components, "
                             f"a {P.scene.dim}D scene has {nd}")
        U[k] = u
    full = U.ravel()
    return full if P.keep is None else full[P.keep]


def interface_normal_forces(P, pairs) -> np.ndarray:
    """(m,) the normal force (N, compression positive) of each interface of P from a DEM run's
    contact forces per block pair, ``pairs`` = [[id_a, id_b, fx, fy, fz], ...], the force on
    block b from block a (N, global axes; a 2D scene's fz is ignored):
    N_k = F(a_k -> b_k) . n_k, with n_k the interface's normal out of its block a_k into b_k
    (:mod:`limit.geom.interfaces`). A block pair with several interfaces (a compound block's
    parts) shares its force among them by area. ValueError names a block the scene lacks."""
    idx = {b.id: i for i, b in enumerate(P.scene.blocks)}
    d = P.scene.dim
    force = {}
    for row in pairs:
        a, b, f = row[0], row[1], np.asarray(row[2:2 + 3], dtype=float)[:d]
        for name in (a, b):
            if name not in idx:
                raise ValueError(f"contact forces: block '{name}' is not in the scene")
        force[(idx[a], idx[b])] = f
    I = P.I
    area_of_pair: dict = {}
    for k in range(len(I)):
        key = frozenset((int(I.a[k]), int(I.b[k])))
        area_of_pair[key] = area_of_pair.get(key, 0.0) + float(I.area[k])
    out = np.zeros(len(I))
    for k in range(len(I)):
        a, b = int(I.a[k]), int(I.b[k])
        f = force.get((a, b))
        if f is None:
            f = -force[(b, a)] if (b, a) in force else None
        if f is not None:
            out[k] = float(f @ np.asarray(I.normal[k], dtype=float)) * float(I.area[k]) / area_of_pair[frozenset((a, b))]
    return out


def _from_forces(P, lp_sol, N, forces: dict, deadline: float) -> dict:
    """The large route's N iteration (:func:`limit.solve.step2_large.run_start`) from the normal
    forces of a DEM run's equilibrium (:func:`interface_normal_forces`, tension clipped to 0):
    N* of each friction row its interface's normal force. The run_start dict."""
    from limit.solve import step2_large

    n_if = np.maximum(interface_normal_forces(P, forces.get("pairs") or []), 0.0)
    x = np.zeros(P.model.n_x)
    normal = np.asarray(P.model.normal_col, dtype=bool)
    x_if = np.asarray(P.model.x_iface)
    per = np.bincount(x_if[normal], minlength=len(P.I)).astype(float)  # normal components per interface
    x[normal] = n_if[x_if[normal]] / np.maximum(per[x_if[normal]], 1.0)
    alpha_ref = lp_sol.alpha if lp_sol is not None and lp_sol.status == Status.OPTIMAL else np.inf
    return step2_large.run_start(P, N, step2_large.nstar_of(P, x), alpha_ref, deadline=deadline)


def multipliers(P, N, vh: np.ndarray) -> tuple[np.ndarray, float]:
    """(lamh (n_faces,) >= 0, relative misfit): the flow ``Gh lamh`` nearest to the interface
    motions ``Eh^T vh``, interface by interface (scaled units of :mod:`limit.solve.nlp_problem`).
    The misfit is |Gh lamh - Eh^T vh| / |Eh^T vh|: 0 for a motion without dilatancy."""
    d = P.Eh.T @ vh
    lam = np.zeros(P.model.n_faces)
    G = N.Gh.tocsc()
    face_if = np.asarray(P.model.iface)
    x_if = np.asarray(P.model.x_iface)
    rows_of = _groups(x_if)
    cols_of = _groups(face_if)
    miss = 0.0
    for k, cols in cols_of.items():
        rows = rows_of.get(k)
        if rows is None or not np.any(d[rows]):
            continue
        Gk = G[:, cols][rows].toarray()
        lam[cols], r = nnls(Gk, d[rows])
        miss += r * r
    ref = float(np.linalg.norm(d))
    return lam, (np.sqrt(miss) / ref if ref > 0 else 0.0)


def _groups(labels: np.ndarray) -> dict:
    order = np.argsort(labels, kind="stable")
    keys, starts = np.unique(labels[order], return_index=True)
    return {int(k): order[a:b] for k, a, b in zip(keys, starts, np.append(starts[1:], order.size))}


def solve(P, lp_sol, displacement: dict, backend: str | None = None, time_budget: float = SLA_BUDGET,
          forces: dict | None = None) -> dict:
    """The lowest verified frictional collapse state from the flowing sets of a DEM displacement
    and, where the run gives them, its contact forces.

    With ``forces`` (a run's ``held_forces``: {"alpha", "pairs"}), first the large route's N
    iteration from their normal forces (:func:`_from_forces`, within ``time_budget`` s). Then
    the piece LP of each rung of :data:`TAU` (up to the first verified one); where none
    verifies, the successive LP (:func:`limit.solve.nlp.solve_sla`) from the mechanism nearest to
    each flowing set in turn (:func:`limit.solve.nlp.phase1` with a unit cost on the multipliers of
    the faces outside it, the LP's statics), within ``time_budget`` s, keeping the lowest verified
    point. Returns {"status": "optimal" | "failed", "alpha", "z" (scaled point of N, or None),
    "N", "tau" (the rung that gave it; None: the contact forces), "n_flowing", "how" ("piece LP",
    "successive LP" or "N iteration from the contact forces"),
    "residuals" (its check's, when verified),
    "misfit", "tried": [{"tau", "how", "n_flowing", "alpha", "verified", "reason"}], "time_s",
    "reason"}. ``backend`` of the LPs (:mod:`limit.solve.lpsub`; None: "highs" up to the setting
    ``highs_max_vars`` unknowns, else "clarabel")."""
    from limit.solve.nlp_problem import build

    t0 = time.perf_counter()
    N = build(P)
    backend = backend or ("highs" if N.n <= settings.of(P).highs_max_vars else "clarabel")
    vh = dof_vector(P, displacement) * P.Df
    out = {"status": Status.FAILED, "alpha": None, "z": None, "N": N, "tau": None, "n_flowing": 0, "how": None,
           "tried": []}
    have_lp = lp_sol is not None and lp_sol.status == Status.OPTIMAL
    alpha_ref = lp_sol.alpha if have_lp else None
    best = None
    if forces:
        r = _from_forces(P, lp_sol, N, forces, t0 + time_budget)
        best = _record(out, N, r["z"] if r.get("verified") else None, r.get("how") or r.get("reason") or "",
                       alpha_ref, None, "N iteration from the contact forces", 0, best)
        out["tried"][-1]["iterations"] = int(r.get("iterations") or 0)
    if not np.any(vh):
        return _outcome(out, best, t0, misfit=None, why="the displacement moves no free block")
    lam, misfit = multipliers(P, N, vh)
    out["misfit"] = misfit
    if lam.max(initial=0.0) <= 0.0:
        return _outcome(out, best, t0, misfit=misfit, why="no joint of the displacement flows")
    statics = (lp_sol.alpha, lp_sol.x / P.Dx) if have_lp else (0.0, np.zeros(P.model.n_x))
    rungs, seen = [], set()
    for tau in TAU:
        flows = lam > tau * lam.max()
        if flows.tobytes() not in seen:
            seen.add(flows.tobytes())
            rungs.append((tau, flows))
    for tau, flows in rungs:  # the piece LPs: a superset's alpha is no lower, so the first verified ends them
        z = N.join(statics[0], statics[1], vh, np.where(flows, lam, 0.0))
        zp, note = nlp.polish(N, z, backend, rule="support")
        best = _record(out, N, zp, note, alpha_ref, tau, "piece LP", int(flows.sum()), best)
        if out["tried"][-1]["verified"]:
            break
    deadline = t0 + time_budget
    piece_verified = any(t["verified"] for t in out["tried"] if t["how"] == "piece LP")
    for tau, flows in ([] if piece_verified else rungs):
        if time.perf_counter() > deadline:
            out["tried"].append({"tau": tau, "how": "successive LP", "n_flowing": int(flows.sum()), "alpha": None,
                                 "verified": False, "reason": f"not begun: time budget of {time_budget:g} s spent"})
            continue
        z0, why = nlp.phase1(N, N.join(statics[0], statics[1], vh, lam), backend, face_cost=(~flows).astype(float))
        if z0 is None:
            out["tried"].append({"tau": tau, "how": "successive LP", "n_flowing": int(flows.sum()), "alpha": None,
                                 "verified": False, "reason": why})
            continue
        z, _ = nlp.solve_sla(N, z0, backend, deadline=deadline)
        zf, ok, _, why, note = nlp.finish(N, z, alpha_ref, backend)
        best = _record(out, N, zf if ok else None, note if ok else f"{why} ({note})", alpha_ref, tau,
                       "successive LP", int(flows.sum()), best)
    return _outcome(out, best, t0, misfit=misfit,
                    why=f"no flowing set of the displacement gave a verified point ({len(out['tried'])} tried)")


def _outcome(out, best, t0, misfit, why) -> dict:
    """The result dict of :func:`solve`: ``best``'s point, else failed with ``why``."""
    out = {**out, "misfit": misfit, "time_s": time.perf_counter() - t0}
    if best is None:
        return {**out, "reason": why}
    z, tau, n, how, res = best
    N = out["N"]
    return {**out, "status": Status.OPTIMAL, "alpha": float(z[N.ia]), "z": z, "tau": tau, "n_flowing": n, "how": how,
            "residuals": res, "reason": ""}


def _record(out, N, zp, note, alpha_ref, tau, how, n_flowing, best):
    """Append one try to ``out["tried"]``; the better of ``best`` and a verified ``zp``."""
    entry = {"tau": tau, "how": how, "n_flowing": n_flowing, "alpha": None, "verified": False}
    if zp is None:
        entry["reason"] = note
    else:
        ok, res, why = nlp.check(N, zp, alpha_ref)
        entry.update(alpha=float(zp[N.ia]), verified=bool(ok), reason=why or note)
        if ok and (best is None or zp[N.ia] < best[0][N.ia]):
            best = (zp, tau, n_flowing, how, res)
    out["tried"].append(entry)
    return best
