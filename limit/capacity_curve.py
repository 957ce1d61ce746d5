"""Nonlinear kinematic analysis of a 2D mechanism: the load multiplier alpha(d) as the
mechanism moves through finite displacements, down to alpha = 0 (NTC 2018 C8.7.1;
Circolare 617/2009 C8A.4.2, kept by the 2019 Circolare's C8.7.1).

The mechanism's joints are read from its velocities (:func:`joints`): at each interface
end point, contact is kept (no normal relative velocity there; an associative LP's
dilatancy is dropped, sliding is Coulomb's) unless it opens beyond the dilatancy; where
the joint does not slip, no tangential relative velocity either. So a hinge gives two
equations, a joint that does nothing three, an open one none (a sliding joint would give
two, one when it also turns about a corner; sliding mechanisms are refused for now, the
follower being checked on rocking mechanisms only). Those points and directions are carried
with the blocks (a hinge's point with block a; a sliding corner with its own block), and
at each configuration the velocities are the null space of the joint equations (the one
closest to the previous velocities when several remain). The multiplier is the ratio of
the dead load's to the live load's power, -sum f0 . v / sum fL . v, with the loads'
forces at the blocks' current centroids (self weight and body forces, exact; a point
force's moment is kept at its initial value). Each step moves every block by the rigid
motion of its velocity held over the step (a rotation about its instantaneous centre),
with the velocities of the step's midpoint; new contacts are not looked for.

Control point: the centroid of the block with the largest horizontal virtual
displacement; its horizontal displacement along the live load is ``d`` (m). Spectral
displacement d* = d sum P_i dx_i^2 / (dx_k sum P_i dx_i) (C8A.4.5) and acceleration
a* = alpha g / (e* FC) (C8A.4.4); du* = 0.4 d0* and Ts = 2 pi sqrt(ds*/as*) with
ds* = 0.4 du* (C8A.4.2.3 / C8A.4.7).
"""
from __future__ import annotations

import numpy as np

from .kinematic_check import FC_DEFAULT, horizontal_direction, linear, point_velocities, weights

#: relative tolerance of a joint's relative velocity (of the largest in the mechanism)
JOINT_TOL = 1e-6


def _rot(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s], [s, c]])


def _perp(r):
    return np.array([-r[1], r[0]])


class Chain:
    """The blocks' poses and the mechanism's joints (2D)."""

    def __init__(self, scene, interfaces, mechanism: dict):
        if scene.dim != 2:
            raise ValueError("the nonlinear kinematic analysis follows 2D mechanisms only")
        self.scene = scene
        self.free = [int(i) for i in scene.free]
        self.col = {i: k for k, i in enumerate(self.free)}
        self.c0 = np.array([b.centroid for b in scene.blocks])
        self.c = self.c0.copy()          # current centroids (n, 2)
        self.th = np.zeros(len(scene.blocks))  # rotations from the start (rad)
        v0 = np.zeros(3 * len(self.free))
        for i in self.free:
            v0[3 * self.col[i]:3 * self.col[i] + 3] = mechanism.get(scene.blocks[i].id, [0.0, 0.0, 0.0])
        self.v = v0
        self.rows = self.joints(interfaces, v0)

    def body(self, i, p):
        """Block i's body coordinates of world point p (at the start)."""
        return np.asarray(p, float) - self.c0[i]

    def world(self, i, r):
        return self.c[i] + _rot(self.th[i]) @ r

    def vel(self, v, i, p):
        """Velocity (2,) of world point p on block i (zero for a fixed block)."""
        if i not in self.col:
            return np.zeros(2)
        u = v[3 * self.col[i]:3 * self.col[i] + 3]
        return u[:2] + u[2] * _perp(p - self.c[i])

    def joints(self, I, v) -> list:
        """Joint equations: (kind, a, b, owner of the point, body point, direction owner, body
        direction); kind 'n' (no normal relative velocity at the point) or 't' (no tangential)."""
        corners = {i: np.asarray(b.poly.vertices, float) for i, b in enumerate(self.scene.blocks)}
        rel = []
        for k in range(len(I)):
            a, b = int(I.a[k]), int(I.b[k])
            n, t = I.normal[k], I.t1[k]
            ends = np.asarray(I.polygons[k], float)[:2]
            dv = [self.vel(v, b, p) - self.vel(v, a, p) for p in ends]
            rel.append((k, a, b, n, t, ends, dv))
        scale = max((float(np.abs(x).max()) for *_, dv in rel for x in dv), default=0.0)
        tol = JOINT_TOL * max(scale, 1e-300)
        rows = []
        for k, a, b, n, t, ends, dv in rel:
            mu = float(I.mu[k])
            slip = abs(float(dv[0] @ t))
            if slip > tol and any(float(d @ n) <= mu * slip + tol for d in dv):
                raise ValueError(f"joint {self.scene.blocks[a].id}|{self.scene.blocks[b].id} slides: the nonlinear "
                                 "kinematic analysis follows rocking mechanisms only")
            contact = [float(d @ n) <= mu * slip + tol for d in dv]
            for p, on in zip(ends, contact):
                if not on:
                    continue
                near_b = float(np.min(np.linalg.norm(corners[b] - p, axis=1))) < 1e-9 * (1.0 + float(np.abs(p).max()))
                owner = b if slip > tol and near_b else a  # a corner of b sliding along a's face
                rows.append(("n", a, b, owner, self.body(owner, p), a, n.copy()))
            if slip <= tol and any(contact):
                p = ends[int(np.argmax(contact))]
                rows.append(("t", a, b, a, self.body(a, p), a, t.copy()))
        return rows

    def matrix(self) -> np.ndarray:
        """(equations, 3 n_free) joint equations at the current configuration."""
        A = np.zeros((len(self.rows), 3 * len(self.free)))
        for r, (kind, a, b, owner, rp, downer, d) in enumerate(self.rows):
            p = self.world(owner, rp)
            e = _rot(self.th[downer]) @ d
            for blk, sgn in ((b, 1.0), (a, -1.0)):
                if blk in self.col:
                    j = 3 * self.col[blk]
                    A[r, j:j + 2] += sgn * e
                    A[r, j + 2] += sgn * e @ _perp(p - self.c[blk])
        return A

    def velocities(self, prev: np.ndarray) -> np.ndarray:
        """The joint-compatible velocities closest to ``prev`` (same scale as prev)."""
        A = self.matrix()
        if not len(A):
            return prev.copy()
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
        """Centroid velocities v (3 n_free) -> per-block twists [velocity of the body point at
        the world origin (2), w]: a description of the motion that does not depend on where
        the block is."""
        t = v.reshape(-1, 3).copy()
        for k, i in enumerate(self.free):
            t[k, :2] -= t[k, 2] * _perp(self.c[i])
        return t.ravel()

    def at_centroids(self, tw) -> np.ndarray:
        """Twists -> centroid velocities at the current configuration."""
        v = tw.reshape(-1, 3).copy()
        for k, i in enumerate(self.free):
            v[k, :2] += v[k, 2] * _perp(self.c[i])
        return v.ravel()

    def move(self, tw, h):
        """Every free block by the rigid motion of its twist held for a time h (a rotation about
        its instantaneous centre perp(u_O) / w, or a translation)."""
        for k, i in enumerate(self.free):
            uo, w = tw[3 * k:3 * k + 2], tw[3 * k + 2]
            if abs(w * h) < 1e-15:
                self.c[i] = self.c[i] + uo * h
            else:
                ic = _perp(uo) / w
                self.c[i] = ic + _rot(w * h) @ (self.c[i] - ic)
            self.th[i] += w * h


def follow(scene, mechanism: dict, alpha0: float | None = None, *, interfaces=None, steps: int = 400,
           theta_max: float = 0.5, fc: float = FC_DEFAULT) -> dict:
    """alpha along the mechanism (module docstring) until it reaches zero, or until a block
    turned ``theta_max`` rad, in ``steps`` equal steps of the control displacement. Returns
    {"d" (m), "alpha", "rotation" (the control block's, rad, counter-clockwise), "d_work" (m: the
    live load's work-conjugate displacement sum fL_i . u_i / sum |fL_i|, the DEM's control
    displacement; body forces), "d0" (m, None
    when alpha stays > 0), "control" (block id),
    "spectral": {"d_star" m, "a_star" m/s^2, "d0_star", "du_star", "ds_star", "as_star",
    "Ts" s, "e_star", "M_star"}, "alpha0" (the start's multiplier, by the same ratio)}."""
    from .interfaces import find_interfaces
    from .loads import dead_and_live

    I = find_interfaces(scene) if interfaces is None else interfaces
    ch = Chain(scene, I, mechanism)
    f0, fL = dead_and_live(scene)
    dirn = horizontal_direction(scene)
    idx, pts, P = weights(scene)
    dx = point_velocities(scene, mechanism, idx, pts) @ dirn
    k = int(np.argmax(np.abs(np.array([ch.vel(ch.v, i, ch.c0[i]) @ dirn for i in ch.free]))))
    ctrl = ch.free[k]
    dxk = float(ch.vel(ch.v, ctrl, ch.c0[ctrl]) @ dirn)  # the control point's virtual displacement
    sign = 1.0 if dxk > 0 else -1.0

    def alpha_of(v):
        V = v.reshape(-1, 3)
        den = float(np.sum(fL * V))
        return -float(np.sum(f0 * V)) / den if den != 0 else np.nan

    def control_rate(v):
        return sign * float(ch.vel(v, ctrl, ch.c[ctrl]) @ dirn)

    v = ch.velocities(ch.v)
    a_start = alpha_of(v)
    # step size: the control point's displacement at which a block has turned theta_max
    wmax = float(np.max(np.abs(v.reshape(-1, 3)[:, 2]), initial=0.0))
    rate = control_rate(v)
    if rate <= 0:
        raise ValueError("the control point does not move along the live load")
    span = theta_max * rate / wmax if wmax > 0 else 0.1 * float(np.ptp(ch.c0, axis=0).max())
    h = span / steps
    d, al, rot, x0 = [0.0], [a_start], [0.0], ch.c[ctrl] @ dirn
    fl_den = float(np.linalg.norm(fL[:, :2], axis=1).sum())
    dwork = [0.0]
    d0 = None
    for _ in range(steps):  # midpoint rule on the twists
        v = v / control_rate(v)
        t0 = ch.twist(v)
        save = (ch.c.copy(), ch.th.copy())
        ch.move(t0, 0.5 * h)
        vm = ch.velocities(ch.at_centroids(t0))
        vm = vm / control_rate(vm)
        tm = ch.twist(vm)
        ch.c, ch.th = save
        ch.move(tm, h)
        v = ch.velocities(ch.at_centroids(tm))
        a = alpha_of(v)
        d.append(sign * (ch.c[ctrl] @ dirn - x0))
        al.append(a)
        rot.append(float(ch.th[ctrl]))
        du = np.array([ch.c[i] - ch.c0[i] for i in ch.free])
        dwork.append(float(np.sum(fL[:, :2] * du)) / fl_den if fl_den > 0 else float("nan"))
        if a <= 0:
            # inverse quadratic interpolation d(alpha) through the last three points at alpha = 0
            m = min(3, len(d))
            d0 = float(np.polyval(np.polyfit(al[-m:], d[-m:], m - 1), 0.0))
            break
    d, al = np.array(d), np.array(al)
    lin = linear(scene, mechanism, alpha0 if alpha0 is not None else a_start, fc)
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
        spec.update(d0_star=d0s, du_star=du, ds_star=ds, as_star=as_, Ts=2 * np.pi * np.sqrt(ds / as_) if as_ > 0 else None)
    return {"d": d.tolist(), "alpha": al.tolist(), "rotation": rot, "d_work": dwork, "d0": d0, "control": scene.blocks[ctrl].id,
            "alpha0": a_start, "spectral": spec, "n_joint_equations": len(ch.rows)}
