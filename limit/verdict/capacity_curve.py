"""Nonlinear kinematic analysis of a 2D or 3D mechanism: the load multiplier alpha(d) as the
mechanism moves through finite displacements, down to alpha = 0 (NTC 2018 C8.7.1;
Circolare 617/2009 C8A.4.2, kept by the 2019 Circolare's C8.7.1).

The mechanism's joints are read from its velocities (:meth:`Chain.joints`): at each
interface corner (a 2D interface's two ends, a 3D one's polygon corners) contact is kept
(no normal relative velocity there; an associative LP's dilatancy is dropped) unless the
joint opens there; where the joint does not slip, no tangential relative velocity either
(2D: at one contact point; 3D: along both tangents at every contact corner, so no twist is
left). So a 2D hinge gives two equations, a joint that does nothing three, an open one none;
a 3D hinge line leaves one relative rotation. Sliding mechanisms are refused, naming the
joint (the follower is checked on rocking mechanisms only). Points and directions are
carried with block a, and at each configuration the velocities are the null space of the
joint equations (the one closest to the previous velocities when several remain). The
multiplier is the ratio of the dead load's to the live load's power, -sum f0 . v / sum
fL . v, with the loads' forces at the blocks' current centroids (self weight and body
forces, exact; a point force's moment is kept at its initial value). Each step moves
every block by the exact screw motion of its twist held over the step (2D: a rotation
about its instantaneous centre), with the twists of the step's midpoint; new contacts
are not looked for.

Control point: the centroid of the block with the largest horizontal virtual
displacement; its horizontal displacement along the live load is ``d`` (m). Spectral
displacement d* = d sum P_i dx_i^2 / (dx_k sum P_i dx_i) (C8A.4.5) and acceleration
a* = alpha g / (e* FC) (C8A.4.4); du* = 0.4 d0* and Ts = 2 pi sqrt(ds*/as*) with
ds* = 0.4 du* (C8A.4.2.3 / C8A.4.7).
"""
from __future__ import annotations

import numpy as np

from limit.model.dims import rigid_velocity
from limit.verdict.kinematic_check import FC_DEFAULT, horizontal_direction, linear, point_velocities, weights

def _screw(w, h: float, d: int) -> tuple[np.ndarray, np.ndarray]:
    """(E, J) of a constant spatial twist (v_O, w) held for h: a point moves x -> E x + J v_O
    and a frame R -> E R, with E = exp(h [w]x) and J = int_0^h exp(s [w]x) ds (the solution of
    x' = v_O + w x x; Rodrigues' formula and its integral)."""
    if d == 2:
        a = float(w) * h
        if abs(a) < 1e-12:
            return np.eye(2), h * np.array([[1.0, -0.5 * a], [0.5 * a, 1.0]])
        c, s, ww = np.cos(a), np.sin(a), float(w)
        return np.array([[c, -s], [s, c]]), np.array([[s, c - 1.0], [1.0 - c, s]]) / ww
    w = np.asarray(w, dtype=float)
    n = float(np.linalg.norm(w))
    K = np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])
    a = n * h
    if a < 1e-12:
        return np.eye(3) + h * K, h * np.eye(3) + 0.5 * h * h * K
    E = np.eye(3) + np.sin(a) / n * K + (1.0 - np.cos(a)) / n ** 2 * K @ K
    J = h * np.eye(3) + (1.0 - np.cos(a)) / n ** 2 * K + (a - np.sin(a)) / n ** 3 * K @ K
    return E, J


class SlidingJoint(ValueError):
    """The mechanism slides at a joint in contact: the joint equations cannot follow it."""


#: relative tolerance of a joint's relative velocity (of the largest in the mechanism)
JOINT_TOL = 1e-6


class Chain:
    """The blocks' poses (centroids c, rotations R from the start) and the mechanism's joints,
    2D or 3D. Generalised velocities per free block: 2D [ux, uy, w], 3D [ux, uy, uz, wx, wy, wz]
    at the current centroid."""

    def __init__(self, scene, interfaces, mechanism: dict):
        self.scene = scene
        self.d = d = scene.dim
        self.nd = 3 if d == 2 else 6
        self.free = [int(i) for i in scene.free]
        self.col = {i: k for k, i in enumerate(self.free)}
        self.c0 = np.array([b.centroid for b in scene.blocks], dtype=float)
        self.c = self.c0.copy()                                     # (n, d) m
        self.R = np.repeat(np.eye(d)[None], len(scene.blocks), 0)  # (n, d, d)
        v0 = np.zeros(self.nd * len(self.free))
        for i in self.free:
            v0[self.nd * self.col[i]:self.nd * (self.col[i] + 1)] = mechanism.get(scene.blocks[i].id, np.zeros(self.nd))
        self.v = v0
        self.rows = self.joints(interfaces, v0)

    def gen(self, v, k):
        """Free block number k's generalised velocity (nd,) in v: [u (d,), w (1 in 2D, 3 in 3D)]."""
        return v[self.nd * k:self.nd * (k + 1)]

    def uw(self, v, k):
        """(u (d,), w (scalar in 2D, (3,) in 3D)) of free block number k in v."""
        x = self.gen(v, k)
        return x[:self.d], (x[2] if self.d == 2 else x[3:])

    def body(self, i, p):
        """Block i's body coordinates of world point p (at the start)."""
        return np.asarray(p, float) - self.c0[i]

    def world(self, i, r):
        return self.c[i] + self.R[i] @ r

    def vel(self, v, i, p):
        """Velocity (d,) of world point p on block i (zero for a fixed block)."""
        if i not in self.col:
            return np.zeros(self.d)
        return rigid_velocity(self.gen(v, self.col[i]), np.asarray(p, float) - self.c[i], self.d)

    def joints(self, I, v) -> list:
        """Joint equations: (kind, a, b, body point on a, body direction on a), kind 'n' (no
        normal relative velocity at the point) or 't' (no tangential relative velocity along
        the direction). Points: a 2D interface's two ends, a 3D interface's polygon corners."""
        rel = []
        for k in range(len(I)):
            a, b = int(I.a[k]), int(I.b[k])
            pts = np.asarray(I.polygons[k], float)
            pts = pts[:2] if self.d == 2 else pts
            dv = np.array([self.vel(v, b, p) - self.vel(v, a, p) for p in pts])
            rel.append((k, a, b, pts, dv))
        scale = max((float(np.abs(dv).max()) for *_, dv in rel if dv.size), default=0.0)
        tol = JOINT_TOL * max(scale, 1e-300)
        rows = []
        for k, a, b, pts, dv in rel:
            n = I.normal[k]
            dn = dv @ n
            slip = float(np.linalg.norm(dv - dn[:, None] * n, axis=1).max(initial=0.0))
            contact = dn <= float(I.mu[k]) * slip + tol
            if slip > tol and contact.any():
                raise SlidingJoint(f"joint {self.scene.blocks[a].id}|{self.scene.blocks[b].id} slides: the nonlinear "
                                 "kinematic analysis follows rocking mechanisms only")
            if slip > tol:  # an open joint: no equation
                continue
            tdirs = [I.t1[k]] if self.d == 2 else [I.t1[k], I.t2[k]]
            on = pts[contact]
            rows += [("n", a, b, self.body(a, p), n.copy()) for p in on]
            for p in (on[:1] if self.d == 2 else on):  # 3D: at every corner, so no twist is left
                rows += [("t", a, b, self.body(a, p), np.asarray(t, float).copy()) for t in tdirs]
        return rows

    def matrix(self) -> np.ndarray:
        """(equations, nd n_free) joint equations at the current configuration."""
        d, nd, m = self.d, self.nd, len(self.rows)
        if not hasattr(self, "_rows"):  # the rows as arrays, once (the joints do not change)
            a, b = (np.array([r[k] for r in self.rows], dtype=int) for k in (1, 2))
            col = {i: np.array([self.col.get(int(x), -1) for x in blk]) for i, blk in (("a", a), ("b", b))}
            self._rows = (a, b, np.array([r[3] for r in self.rows], dtype=float).reshape(m, d),
                          np.array([r[4] for r in self.rows], dtype=float).reshape(m, d), col["a"], col["b"])
        a, b, rp, dv, col_a, col_b = self._rows
        Ra = self.R[a]
        p = self.c[a] + np.einsum("kij,kj->ki", Ra, rp)
        e = np.einsum("kij,kj->ki", Ra, dv)
        A = np.zeros((m, nd * len(self.free)))
        rows = np.arange(m)
        for blk, col, sgn in ((b, col_b, 1.0), (a, col_a, -1.0)):
            on = col >= 0
            if not on.any():
                continue
            r, j, ee = rows[on], nd * col[on], e[on]
            q = p[on] - self.c[blk[on]]
            ang = (ee[:, 1] * q[:, 0] - ee[:, 0] * q[:, 1])[:, None] if d == 2 else np.cross(q, ee)
            A[r[:, None], j[:, None] + np.arange(d)] += sgn * ee
            A[r[:, None], j[:, None] + d + np.arange(nd - d)] += sgn * ang
        return A

    def velocities(self, prev: np.ndarray) -> np.ndarray:
        """The joint-compatible velocities closest to ``prev`` (same scale as prev)."""
        A = self.matrix()
        if not len(A):
            return prev.copy()
        if A.shape[0] > A.shape[1]:  # same null space, from the square triangular factor
            A = np.linalg.qr(A, mode="r")
        _, s, Vt = np.linalg.svd(A)
        rank = int(np.sum(s > 1e-10 * max(s.max(initial=0.0), 1e-300)))
        N = Vt[rank:].T
        if N.shape[1] == 0:
            raise ValueError("the joints lock the mechanism: no motion left")
        v = N @ (N.T @ prev)
        nv = float(np.linalg.norm(v))
        if nv <= 1e-9 * float(np.linalg.norm(prev)):
            raise ValueError("the joints no longer allow the mechanism's motion")
        return v * (float(np.linalg.norm(prev)) / nv)

    def twist(self, v) -> np.ndarray:
        """Centroid velocities v -> per-block spatial twists [velocity of the body point at the
        world origin (d), w]: a description of the motion that does not depend on where the
        block is."""
        t = v.copy()
        for k, i in enumerate(self.free):
            t[self.nd * k:self.nd * k + self.d] = rigid_velocity(self.gen(v, k), -self.c[i], self.d)
        return t

    def at_centroids(self, tw) -> np.ndarray:
        """Twists -> centroid velocities at the current configuration."""
        v = tw.copy()
        for k, i in enumerate(self.free):
            v[self.nd * k:self.nd * k + self.d] = rigid_velocity(self.gen(tw, k), self.c[i], self.d)
        return v

    def move(self, tw, h):
        """Every free block by the rigid motion of its twist held for a time h (exact screw
        motion, :func:`_screw`)."""
        for k, i in enumerate(self.free):
            uo, w = self.uw(tw, k)
            E, J = _screw(w, h, self.d)
            self.c[i] = E @ self.c[i] + J @ uo
            self.R[i] = E @ self.R[i]

    def angle(self, i) -> float:
        """Block i's rotation from the start (rad): 2D signed, counter-clockwise; 3D its
        magnitude."""
        return rotation_angle(self.R[i], self.d)


def rotation_angle(R: np.ndarray, d: int) -> float:
    """The angle (rad) of a rotation matrix R (d, d): 2D signed, counter-clockwise; 3D its magnitude."""
    if d == 2:
        return float(np.arctan2(R[1, 0], R[0, 0]))
    return float(np.arccos(np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0)))


def follow(scene, mechanism: dict, alpha0: float | None = None, *, interfaces=None, steps: int = 400,
           theta_max: float = 0.5, fc: float = FC_DEFAULT) -> dict:
    """alpha along the mechanism (module docstring) until it reaches zero, or until a block
    turned ``theta_max`` rad, in ``steps`` equal steps of the control displacement. Returns
    {"d" (m), "alpha", "rotation" (the control block's, rad: 2D counter-clockwise, 3D the angle's magnitude), "d_work" (m: the
    live load's work-conjugate displacement sum fL_i . u_i / sum |fL_i|, the DEM's control
    displacement; body forces), "d0" (m, None
    when alpha stays > 0), "control" (block id),
    "spectral": {"d_star" m, "a_star" m/s^2, "d0_star", "du_star", "ds_star", "as_star",
    "au_star" (a* at du*), "Ts" s, "e_star", "M_star"}, "alpha0" (the start's multiplier, by the same ratio)}.
    BLAS runs on one thread meanwhile (small dense factorisations, as in :func:`limit.analyse`;
    a 3D wall of 24 blocks took 28 s with two busy threads, 5.8 s with one)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        return _follow(scene, mechanism, alpha0, interfaces, steps, theta_max, fc)


def _follow(scene, mechanism, alpha0, interfaces, steps, theta_max, fc) -> dict:
    from limit.geom.interfaces import find_interfaces
    from limit.model.loads import dead_and_live

    I = find_interfaces(scene) if interfaces is None else interfaces
    if getattr(scene, "ties", ()) or I.bonded or bool((I.fc > 0).any()):
        raise ValueError("the capacity curve follows the loads' work alone, and this scene has "
                         + ("tie rods" if getattr(scene, "ties", ()) else "bonded or crushing joints")
                         + ", whose work along the mechanism it does not count")
    ch = Chain(scene, I, mechanism)
    f0, fL = dead_and_live(scene)
    dirn = horizontal_direction(scene)
    k = int(np.argmax(np.abs(np.array([ch.vel(ch.v, i, ch.c0[i]) @ dirn for i in ch.free]))))
    ctrl = ch.free[k]
    dxk = float(ch.vel(ch.v, ctrl, ch.c0[ctrl]) @ dirn)  # the control point's virtual displacement
    sign = 1.0 if dxk > 0 else -1.0

    def alpha_of(v):
        V = v.reshape(-1, ch.nd)
        den = float(np.sum(fL * V))
        return -float(np.sum(f0 * V)) / den if den != 0 else np.nan

    def control_rate(v):
        return sign * float(ch.vel(v, ctrl, ch.c[ctrl]) @ dirn)

    v = ch.velocities(ch.v)
    a_start = alpha_of(v)
    # step size: the control point's displacement at which a block has turned theta_max
    wmax = float(np.max(np.linalg.norm(v.reshape(-1, ch.nd)[:, ch.d:], axis=1), initial=0.0))
    rate = control_rate(v)
    if rate <= 0:
        raise ValueError("the control point does not move along the live load")
    span = theta_max * rate / wmax if wmax > 0 else 0.1 * float(np.ptp(ch.c0, axis=0).max())
    h = span / steps
    d, al, rot, x0 = [0.0], [a_start], [0.0], ch.c[ctrl] @ dirn
    fl_den = float(np.linalg.norm(fL[:, :ch.d], axis=1).sum())
    dwork = [0.0]
    d0 = None
    for _ in range(steps):  # midpoint rule on the twists
        v = v / control_rate(v)
        t0 = ch.twist(v)
        save = (ch.c.copy(), ch.R.copy())
        ch.move(t0, 0.5 * h)
        vm = ch.velocities(ch.at_centroids(t0))
        vm = vm / control_rate(vm)
        tm = ch.twist(vm)
        ch.c, ch.R = save
        ch.move(tm, h)
        v = ch.velocities(ch.at_centroids(tm))
        a = alpha_of(v)
        d.append(sign * (ch.c[ctrl] @ dirn - x0))
        al.append(a)
        rot.append(ch.angle(ctrl))
        du = np.array([ch.c[i] - ch.c0[i] for i in ch.free])
        dwork.append(float(np.sum(fL[:, :ch.d] * du)) / fl_den if fl_den > 0 else float("nan"))
        if a <= 0:
            # inverse quadratic interpolation d(alpha) through the last three points at alpha = 0
            m = min(3, len(d))
            d0 = float(np.polyval(np.polyfit(al[-m:], d[-m:], m - 1), 0.0))
            break
    out = spectral(scene, mechanism, np.array(d), np.array(al), alpha0 if alpha0 is not None else a_start, fc, d0, ctrl)
    return {**out, "rotation": rot, "d_work": dwork, "control": scene.blocks[ctrl].id, "alpha0": a_start,
            "n_joint_equations": len(ch.rows)}


def spectral(scene, mechanism: dict, d: np.ndarray, al: np.ndarray, alpha0: float, fc: float, d0: float | None,
             ctrl: int) -> dict:
    """{"d", "alpha", "d0", "spectral"} of a capacity curve alpha(d) (d: the control point's
    displacement along the live load, m) of the mechanism that starts as ``mechanism`` with
    multiplier ``alpha0``, control block index ``ctrl``: d* = d sum P_i dx_i^2 / (dx_k sum P_i
    dx_i) and a* = alpha g / (e* FC) (module docstring), and where the curve reaches alpha = 0 at
    d0, d0*, du* = 0.4 d0*, ds* = 0.4 du*, as* = a*(ds*), au* = a*(du*) and Ts = 2 pi sqrt(ds*/as*)."""
    lin = linear(scene, mechanism, alpha0, fc)
    dirn = horizontal_direction(scene)
    idx, pts, P = weights(scene)
    dx = point_velocities(scene, mechanism, idx, pts) @ dirn
    dxk = float(point_velocities(scene, mechanism, np.array([ctrl]), scene.blocks[ctrl].centroid[None])[0] @ dirn)
    g = float(np.linalg.norm(scene.gravity))
    moving = np.abs(dx) > 1e-6 * max(float(np.abs(dx).max(initial=0.0)), 1e-300)
    ratio = float(P[moving] @ dx[moving] ** 2) / (dxk * float(P[moving] @ dx[moving]))
    spec = {"e_star": lin["e_star"], "M_star": lin["M_star"], "d_star": (d * ratio).tolist(),
            "a_star": (al * g / (lin["e_star"] * fc)).tolist()}
    if d0 is not None:
        d0s = d0 * ratio
        du = 0.4 * d0s
        ds = 0.4 * du
        as_ = float(np.interp(ds, d * ratio, al)) * g / (lin["e_star"] * fc)
        au = float(np.interp(du, d * ratio, al)) * g / (lin["e_star"] * fc)
        spec.update(d0_star=d0s, du_star=du, ds_star=ds, as_star=as_, Ts=2 * np.pi * np.sqrt(ds / as_) if as_ > 0 else None,
                    au_star=au)
    return {"d": d.tolist(), "alpha": al.tolist(), "d0": d0, "spectral": spec}
