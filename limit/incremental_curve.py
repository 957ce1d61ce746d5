"""Capacity curve of any mechanism, sliding and mixed ones included, by incremental limit
analysis: the frictional problem (step 2) re-solved on the displaced geometry, step by step,
down to alpha = 0.

At each configuration the blocks hold their poses (rotation R_i and centroid c_i from the
start), and every joint of the undeformed scene is re-measured between the two faces that
formed it, carried with their blocks: both faces are projected on the plane of their
bisecting normal (pointing out of block a), their projections intersected, and the overlap
clipped to where the faces lie within the gap tolerance ``g`` of each other along that normal
(the gap is linear over the plane). What is left is the joint's contact polygon (2D: a
segment); where nothing is left, the joint has opened. A hinge so keeps a sliver along its
line, a sliding joint the overlap of its two faces. New contacts are not looked for: a block
that swings into a neighbour it did not touch at the start goes through it.

The frictional problem on these contacts (:mod:`limit.step2` on the assembled problem, the
loads at the blocks' current centroids) gives alpha and the mechanism of the configuration;
every free block then moves by the exact screw motion of its mechanism twist
(:func:`limit.verdict.capacity_curve._screw`) scaled so that the live load's work-conjugate
displacement (its work per unit of its magnitude) advances by the step ``h`` (forward Euler on
the configuration): every collapse mechanism advances it, whichever block moves most. Each
step's step 2 has the previous configuration's mechanism as a start
(:func:`limit.step2.adopt_dem_state`) and runs without the large-scale route's extra starts (the
setting ``also_iterative`` off; the caller's other settings kept). The gap tolerance ``g`` is a quarter of the largest point displacement of a
step, so that the first-order drift of a hinge over a step stays in contact; it is at least
the scene's ``tolerance``.

Control point, spectral quantities and their sources: :mod:`limit.verdict.capacity_curve`
(the same conversion, from the start's mechanism). Checked in tests/test_incremental_curve.py
against closed forms: a rocking block, alpha = tan(atan(b/h) - theta); a block sliding on a
plane inclined at beta, alpha = tan(phi - beta) at every displacement; a block that slides to
a support's edge and tips over it.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from limit.geom import _clip as clip
from limit.geom.geometry import Polytope, plane_basis, polygon_area_centroid
from limit.geom.interfaces import Interfaces, _frame_fields, find_interfaces
from limit.model.dims import rigid_velocity
from limit.solve.status import ANSWERED, Status
from limit.results.typed import StepResult
from limit.verdict.capacity_curve import _screw, rotation_angle, spectral
from limit.verdict.kinematic_check import FC_DEFAULT, horizontal_direction

#: a step after which alpha rises by more than JUMP x alpha0 is redone at half its size, up to
#: JUMP_HALVINGS times: step 2 at the new configuration missed the state the curve follows (the
#: 3 x 3 opening wall in 10 steps: 0.30 then 0.82, where 20 steps follow its toe rotation to 0)
JUMP = 0.05
JUMP_HALVINGS = 3
#: a curve takes at most this many times its ``steps`` (steps shrink where the mechanism narrows)
MAX_STEPS = 4
#: a face of a block forms a joint's side when its outward normal is within this of the
#: joint normal's direction (1 - cos; about 8 degrees: tilted joints included)
FACE_COS = 1e-2


def _face_of(polys, n, p, tol) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (k, d), outward normal (d,)) of the face among the convex ``polys`` whose
    outward normal is closest to ``n`` and which holds the point ``p`` (within ``tol``)."""
    best, score = None, np.inf
    for poly in polys:
        for f, nf, off in zip(poly.faces, poly.face_normals, poly.face_offsets):
            c = float(nf @ n)
            if c < 1.0 - FACE_COS:
                continue
            dist = abs(float(nf @ p) - off)
            outside = _outside(np.asarray(f, float), nf, p)
            s = dist + max(outside, 0.0) + (1.0 - c)
            if s < score:
                best, score = (np.asarray(f, float), np.asarray(nf, float)), s
    if best is None or score > 10 * tol + 1.0 - np.cos(np.radians(10.0)):
        raise ValueError("a joint's face was not found on its block")
    return best


def _outside(face, n, p) -> float:
    """How far point p lies outside the convex face polygon (negative inside), measured in its
    plane (2D: along the segment)."""
    if face.shape[1] == 2:
        t = face[1] - face[0]
        L = float(np.linalg.norm(t))
        s = float((p - face[0]) @ t) / L
        return max(-s, s - L)
    e = np.roll(face, -1, axis=0) - face
    inward = np.cross(n, e)
    inward /= np.maximum(np.linalg.norm(inward, axis=1), 1e-300)[:, None]
    return float(np.max(-np.einsum("kd,kd->k", inward, p - face)))


@dataclasses.dataclass
class _Joint:
    """One joint of the undeformed scene: blocks a, b, and each side's face in body coordinates
    (vertices relative to the block's initial centroid; outward normal)."""
    k: int
    a: int
    b: int
    fa: np.ndarray
    na: np.ndarray
    fb: np.ndarray
    nb: np.ndarray


class Configuration:
    """The blocks' poses and the joints' contacts at finite displacement."""

    def __init__(self, scene, I0: Interfaces):
        self.scene, self.I0, self.d = scene, I0, scene.dim
        self.c0 = np.array([b.centroid for b in scene.blocks], dtype=float)
        self.c = self.c0.copy()
        self.R = np.repeat(np.eye(self.d)[None], scene.n_blocks, 0)
        self.joints = []
        for k in range(len(I0)):
            a, b = int(I0.a[k]), int(I0.b[k])
            n, p = np.asarray(I0.normal[k], float), np.asarray(I0.centroid[k], float)
            fa, na = _face_of(scene.blocks[a].pieces, n, p, scene.tolerance)
            fb, nb = _face_of(scene.blocks[b].pieces, -n, p, scene.tolerance)
            self.joints.append(_Joint(k, a, b, fa - self.c0[a], na, fb - self.c0[b], nb))

    def world(self, i, r):
        return self.c[i] + r @ self.R[i].T

    def contacts(self, gap: float) -> Interfaces:
        """The joints' contacts at the current poses (module docstring), gap tolerance ``gap`` (m)."""
        d, I0 = self.d, self.I0
        keep, fields = [], []
        for j in self.joints:
            Fa, Fb = self.world(j.a, j.fa), self.world(j.b, j.fb)
            na, nb = self.R[j.a] @ j.na, self.R[j.b] @ j.nb
            n = na - nb
            n /= np.linalg.norm(n)
            o = 0.5 * (Fa.mean(axis=0) + Fb.mean(axis=0))
            # onto the plane midway between the faces: it holds the line where they meet (a hinge)
            o = o + 0.5 * (self._height(o, Fa, na, n) + self._height(o, Fb, nb, n)) * n
            poly = (self._contact_2d if d == 2 else self._contact_3d)(Fa, na, Fb, nb, n, o, gap)
            if poly is not None:
                keep.append(j.k)
                fields.append((n, o, poly))
        return self._interfaces(np.array(keep, dtype=int), fields)

    @staticmethod
    def _height(x, F, nf, n):
        """How far (m) along n the plane of face F (outward normal nf) lies from the points x."""
        return (float(nf @ F[0]) - x @ nf) / float(nf @ n)

    def _gap(self, x, Fa, na, Fb, nb, n):
        """Gap (m) along n between the face planes of a and b at points x (k, d) of the contact
        plane: positive where b's face lies beyond a's."""
        return self._height(x, Fb, nb, n) - self._height(x, Fa, na, n)

    def _contact_2d(self, Fa, na, Fb, nb, n, o, gap):
        t = np.array([n[1], -n[0]])
        sa, sb = (Fa - o) @ t, (Fb - o) @ t
        lo, hi = max(sa.min(), sb.min()), min(sa.max(), sb.max())
        if hi - lo <= 0:
            return None
        ends = o + np.outer([lo, hi], t)
        g = self._gap(ends, Fa, na, Fb, nb, n)
        s = np.array([lo, hi])
        if g.max() > gap:  # clip to g <= gap (g linear along t)
            if g.min() > gap:
                return None
            s_cut = lo + (gap - g[0]) / (g[1] - g[0]) * (hi - lo)
            s = np.array([lo, s_cut]) if g[0] <= gap else np.array([s_cut, hi])
        if s[1] - s[0] <= 0:
            return None
        return o + np.outer(s, t)

    def _contact_3d(self, Fa, na, Fb, nb, n, o, gap):
        e1, e2 = plane_basis(n)

        def proj(F):
            V = F - o
            return np.column_stack([V @ e1, V @ e2])

        A, B = proj(Fa), proj(Fb)
        if polygon_area_centroid(A[None])[0][0] < 0:
            A = A[::-1]
        if polygon_area_centroid(B[None])[0][0] < 0:
            B = B[::-1]
        P = clip.intersect(A[None], B[None], 0.0)[0]
        if len(P) < 3:
            return None
        X = o + P[:, :1] * e1 + P[:, 1:] * e2
        g = self._gap(X, Fa, na, Fb, nb, n)
        P = _clip_halfplane(P, g - gap)
        if len(P) < 3 or polygon_area_centroid(P[None])[0][0] <= 0:
            return None
        return P

    def _interfaces(self, keep, fields) -> Interfaces:
        I0, d, m = self.I0, self.d, len(keep)
        base = dict(dim=d, a=I0.a[keep], b=I0.b[keep], mu=I0.mu[keep])
        if d == 2:
            polys = [p for *_, p in fields]
            n = np.array([f[0] for f in fields]).reshape(m, 2)
            t = np.column_stack([n[:, 1], -n[:, 0]]) if m else np.zeros((0, 2))
            half = np.array([0.5 * np.linalg.norm(p[1] - p[0]) for p in polys])
            cen = np.array([p.mean(axis=0) for p in polys]).reshape(m, 2)
            th = self.scene.thickness
            return Interfaces(**base, normal=n, t1=t, t2=None, centroid=cen, area=2 * half * th, l1=half,
                              l2=np.full(m, 0.5 * th), is_rect=np.ones(m, bool), polygons=polys,
                              local=[np.array([[-h], [h]]) for h in half])
        n = np.array([f[0] for f in fields]).reshape(m, 3)
        o = np.array([f[1] for f in fields]).reshape(m, 3)
        e1, e2 = plane_basis(n) if m else (np.zeros((0, 3)), np.zeros((0, 3)))
        # the contact polygons were made in plane_basis(n[r]) of each row: the same basis here
        return Interfaces(**base, **_frame_fields(n, e1, e2, o, [p for *_, p in fields], self.scene.tolerance))

    def corner_speed(self, mech: np.ndarray) -> float:
        """The largest speed of a free block's corner in the generalised velocities ``mech``
        (n_free, nd) at the blocks' current centroids."""
        d, v = self.d, 0.0
        for k, i in enumerate(self.scene.free):
            r = (self.scene.blocks[i].poly.vertices - self.c0[i]) @ self.R[i].T
            v = max(v, float(np.linalg.norm(rigid_velocity(mech[k], r, d), axis=1).max()))
        return v

    def move(self, mech: np.ndarray, h: float) -> None:
        """Every free block by the screw motion of its generalised velocity (nd,) at its current
        centroid, ``mech`` (n_free, nd), held for h."""
        d = self.d
        for k, i in enumerate(self.scene.free):
            w = mech[k, 2] if d == 2 else mech[k, 3:]
            vo = rigid_velocity(mech[k], -self.c[i], d)  # the velocity of the body point at the origin
            E, J = _screw(w, h, d)
            self.c[i] = E @ self.c[i] + J @ vo
            self.R[i] = E @ self.R[i]

    def scene_now(self):
        """The scene with every block at its current pose (loads' points carried with their blocks)."""
        sc = self.scene
        blocks = []
        for i, b in enumerate(sc.blocks):
            if b.fixed:
                blocks.append(b)
                continue
            mv = [_moved(p, self.R[i], self.c0[i], self.c[i]) for p in (b.poly, *b.parts)]
            blocks.append(dataclasses.replace(b, poly=mv[0], parts=tuple(mv[1:])))

        def carried(loads):
            out = []
            for ld in loads:
                if ld["type"] == "point_force" and "point" in ld and ld["_blocks"]:
                    i = int(ld["_blocks"][0])
                    ld = {**ld, "point": (self.c[i] + self.R[i] @ (np.asarray(ld["point"], float) - self.c0[i])).tolist()}
                out.append(ld)
            return out

        return dataclasses.replace(sc, blocks=blocks, dead=carried(sc.dead), live=carried(sc.live), friction_pairs={})


def _moved(poly: Polytope, R, c0, c) -> Polytope:
    """``poly`` moved rigidly: x -> c + R (x - c0)."""
    def f(X):
        return c + (np.asarray(X, float) - c0) @ R.T

    normals = poly.face_normals @ R.T
    faces = [f(F) for F in poly.faces]
    offsets = np.array([float(nrm @ F[0]) for nrm, F in zip(normals, faces)])
    return Polytope(f(poly.vertices), normals, offsets, faces, poly.measure, f(poly.centroid))


def _clip_halfplane(P: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The part of polygon P (k, 2) where the linear function with values s (k,) at its
    vertices is <= 0 (Sutherland-Hodgman, one plane)."""
    out = []
    k = len(P)
    for i in range(k):
        j = (i + 1) % k
        if s[i] <= 0:
            out.append(P[i])
        if (s[i] <= 0) != (s[j] <= 0):
            out.append(P[i] + (s[i] / (s[i] - s[j])) * (P[j] - P[i]))
    return np.array(out).reshape(-1, 2)


def follow_frictional(scene, alpha0: float | None = None, *, mechanism: dict | None = None,
                      steps: int | None = None, theta_max: float = 0.5, span: float | None = None,
                      fc: float = FC_DEFAULT, options=None, time_budget: float | None = None,
                      progress=None) -> dict:
    """alpha along the mechanism by incremental limit analysis (module docstring), stopping where
    alpha reaches 0. ``span`` (m; default: the control point's displacement at which a block of the
    start's mechanism has turned ``theta_max`` rad, at most the control block's extent along the
    load, and that extent for a mechanism without rotation) is covered in ``steps`` steps of the
    live load's work-conjugate displacement, each shortened where needed so that no block's corner
    moves further than in the first step; past the span the curve goes on while alpha still falls,
    up to :data:`MAX_STEPS` x ``steps`` steps. ``mechanism`` ({block id: generalised velocity})
    and ``alpha0``: the start's (default: step 2 on the undeformed scene). ``steps`` and
    ``time_budget`` (s: no step starts after it) default to the settings ``curve_steps`` and
    ``curve_time_budget`` of ``options`` (:class:`limit.model.assemble.Options`, also step 2's).
    ``progress``: a callable(step, alpha) or None.

    Returns the layout of :func:`limit.verdict.capacity_curve.follow` ("d", "alpha", "rotation",
    "d_work", "d0", "control", "spectral", "alpha0") with "control_centroid" (the control block's
    centroid at each point, m), "method": "incremental", "steps" (the solves made) and "stop" (why
    the curve ends). Where the last step ends with a configuration that cannot carry its dead
    load, that point is moved back to d0, the secant's zero of the last two points, and alpha 0."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        from limit.model.assemble import Options

        st = (options or Options()).settings
        return _follow(scene, alpha0, mechanism, steps or st.curve_steps, theta_max, span, fc, options,
                       st.curve_time_budget if time_budget is None else time_budget, progress)


def _solve(scene, I, options=None, start: dict | None = None):
    """Step 2 on ``scene`` with the contacts ``I``: its part of the result
    (:class:`limit.results.typed.StepResult`: status, alpha, mechanism).
    ``start``: the previous configuration's mechanism {block id: velocity}, tried as a start too
    (:func:`limit.step2.adopt_dem_state`: its joints that open and slide as the piece LP's flowing
    set), so that the curve keeps to the mechanism it follows where step 2's own starts find a
    higher local minimum."""
    from limit import step2
    from limit.model.assemble import assemble
    from limit.solve import lp as lpmod
    from limit.solve.checked_lp import solve_lp

    P = assemble(scene, options, interfaces=I)
    sol, _, _ = solve_lp(P, lpmod.DEFAULT_SOLVER, True, False)
    if sol.status not in (Status.OPTIMAL, Status.UNBOUNDED):  # unbounded: step 2 starts from the dead load
        return StepResult(sol.status)
    state = None if start is None else {"displacement": start, "source": "previous step"}
    return step2.step2(P, sol, method="auto", dem_state=state)  # "skipped": the LP's point is frictional


def _mech_array(scene, mech: dict) -> np.ndarray:
    nd = scene.ndof
    return np.array([mech.get(scene.blocks[i].id, np.zeros(nd)) for i in scene.free], dtype=float).reshape(-1, nd)


def _follow(scene, alpha0, mechanism, steps, theta_max, span, fc, options, budget, progress) -> dict:
    t0 = time.perf_counter()
    from limit.model.loads import dead_and_live

    if getattr(scene, "ties", ()) or any(ld["type"] == "pressure" for ld in (*scene.dead, *scene.live)):
        raise ValueError("the incremental capacity curve carries self weight, body forces and point forces "
                         "with the blocks; this scene has " + ("tie rods" if scene.ties else "pressure loads"))
    I0 = find_interfaces(scene)
    if I0.bonded or bool((I0.fc > 0).any()):
        raise ValueError("the incremental capacity curve follows dry joints; this scene has bonded or crushing joints")
    cfg = Configuration(scene, I0)
    if mechanism is None or alpha0 is None:
        first = _solve(scene, I0, options)  # step 2 as the analysis runs it
        if first.get("status") not in ANSWERED or not first.get("mechanism"):
            raise ValueError(f"step 2 on the undeformed scene gave no mechanism ({first.get('status')})")
        alpha0, mechanism = float(first["alpha"]), first["mechanism"]
    dirn = horizontal_direction(scene)
    d = scene.dim
    U0 = _mech_array(scene, mechanism)
    rates = np.array([U0[k, :d] @ dirn for k in range(len(scene.free))])
    kc = int(np.argmax(np.abs(rates)))
    ctrl = int(scene.free[kc])
    extent = float(np.ptp(scene.blocks[ctrl].poly.vertices @ dirn))
    if span is None:
        wmax = float(np.max(np.abs(U0[:, d:]).reshape(len(U0), -1).max(axis=1), initial=0.0)) if d == 2 else \
            float(np.max(np.linalg.norm(U0[:, d:], axis=1), initial=0.0))
        span = extent if wmax <= 1e-12 * abs(rates[kc]) else min(extent, theta_max * abs(rates[kc]) / wmax)
    x0 = float(cfg.c[ctrl] @ dirn)
    f0, fL = dead_and_live(scene)
    fl_den = float(np.linalg.norm(fL[:, :d], axis=1).sum()) or 1.0

    def power(U, fl):  # the live load's power per unit of its magnitude (m/s for unit rates)
        return float(np.sum(fl * U)) / fl_den

    # the steps advance the live load's work-conjugate displacement, which every collapse
    # mechanism increases (fL . u = 1), whichever block moves most as the mechanism changes
    h = span * power(U0, fL) / abs(rates[kc]) / steps
    # no step moves a block's corner further than the first step does: a mechanism that narrows to
    # a few blocks moves them more per unit of the live load's work, and the steps shrink with it
    delta = h * cfg.corner_speed(U0 / power(U0, fL))
    ds, al, rot, dwork, cc = [0.0], [float(alpha0)], [0.0], [0.0], [cfg.c[ctrl].copy()]
    d0, stop, solves = None, (f"the curve reached its span ({span:.4g} m of the control point's start) with alpha no "
                              "longer falling"), 0
    # each step starts from the previous one's mechanism: no extra route
    from limit.model.assemble import Options

    base = options or Options()
    options = dataclasses.replace(base, settings=base.settings.replace(also_iterative=False))
    U, prev, fL_now = U0, mechanism, fL
    done = 0.0  # the live load's work-conjugate displacement so far
    for step in range(MAX_STEPS * steps):
        if done >= h * steps * (1.0 - 1e-9) and not al[-1] < al[-2] - 1e-6 * abs(al[0]):
            break  # past the span, alpha no longer falling (a sliding plateau): it would not reach 0
        if time.perf_counter() - t0 > budget:
            stop = f"the time budget ({budget:g} s, setting curve_time_budget) ran out after {step} steps"
            break
        rate = power(U, fL_now)
        if rate <= 0:
            stop = "the mechanism does no work against the live load"
            break
        Us = U / rate
        vmax = cfg.corner_speed(Us)
        hs = min(h, delta / vmax) if vmax > 0 else h
        saved = (cfg.c.copy(), cfg.R.copy())
        for halving in range(JUMP_HALVINGS + 1):
            move = hs * vmax
            cfg.move(Us, hs)
            now = cfg.scene_now()
            try:
                part = _solve(now, cfg.contacts(max(scene.tolerance, 0.25 * move)), options, prev)
            except Exception as exc:  # a block that lost every contact, a failed assembly
                part = StepResult(Status.FAILED, reason=f"no solution: {exc}")
            solves += 1
            a = part.get("alpha")
            if not (a is not None and a > al[-1] + JUMP * abs(al[0])) or halving == JUMP_HALVINGS:
                break
            cfg.c, cfg.R = saved[0].copy(), saved[1].copy()  # a jump up: redo the step at half its size
            hs *= 0.5
        done += hs
        ds.append(float(cfg.c[ctrl] @ dirn) - x0)
        rot.append(rotation_angle(cfg.R[ctrl], d))
        cc.append(cfg.c[ctrl].copy())
        du = np.array([cfg.c[i] - cfg.c0[i] for i in scene.free])
        dwork.append(float(np.sum(fL[:, :d] * du)) / fl_den)
        if part.get("status") not in ANSWERED or a is None:
            al.append(0.0 if part.get("status") == Status.INFEASIBLE else float("nan"))
            stop = ("the displaced configuration cannot carry its dead load" if part.get("status") == Status.INFEASIBLE
                    else f"step 2 {part.get('status')} at step {step + 1}: {part.get('reason', '')}")
            if part.get("status") == Status.INFEASIBLE and len(al) >= 3 and np.isfinite(al[-2]):
                # alpha crossed 0 within the step: the secant of the last two points, inside the step
                a1, a2 = al[-3], al[-2]
                slope = (a2 - a1) / (ds[-2] - ds[-3]) if ds[-2] > ds[-3] else 0.0
                d0 = float(np.clip(ds[-2] - a2 / slope, ds[-2], ds[-1])) if slope < 0 else ds[-1]
                f = (d0 - ds[-2]) / (ds[-1] - ds[-2]) if ds[-1] > ds[-2] else 1.0
                for arr in (rot, dwork, cc):  # the last point moved back to d0
                    arr[-1] = arr[-2] + f * (arr[-1] - arr[-2])
                ds[-1], al[-1] = d0, 0.0
            break
        al.append(float(a))
        U, prev, fL_now = _mech_array(now, part["mechanism"]), part["mechanism"], dead_and_live(now)[1]
        if progress is not None:
            progress(step + 1, float(a))
        if a <= 0:
            d0 = float(np.interp(0.0, [al[-1], al[-2]], [ds[-1], ds[-2]]))
            stop = "alpha reached 0"
            break
    else:
        stop = f"{solves} steps made before the span (at most {MAX_STEPS} x curve_steps)"
    out = spectral(scene, mechanism, np.array(ds), np.array(al), alpha0, fc, d0, ctrl)
    return {**out, "rotation": rot, "d_work": dwork, "control": scene.blocks[ctrl].id, "alpha0": float(alpha0),
            "control_centroid": np.array(cc).tolist(), "method": "incremental", "steps": solves, "stop": stop}
