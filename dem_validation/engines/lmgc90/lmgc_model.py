"""LMGC90 side: one scene as rigid polyhedra in LMGC90 (non-smooth contact
dynamics, Jean & Dubois), one load trial per process-wide simulation.

Runs inside the LMGC90 process (``lmgc_main.py``); imports only numpy, scipy
and the compiled core ``compas_lmgc90._lmgc90`` (PyPI ``compas_lmgc90``, used
without its Python wrapper). The job is the host's DEM job
(:mod:`dem_validation.job`): world vertices (a 2D scene's blocks as prisms),
masses, fixed and blocked dofs, per free block the dead and live generalised
forces ``[Fx, Fy, Fz, Mx, My, Mz]`` (N, N m) at its centroid, friction.

LMGC90's gravity is fixed at (0, 0, -9.81) m/s^2, so the scene is turned by
a rotation Q that takes its "up" (-g / |g|) to +z (a 2D scene's y axis), and
each block gets the density m |g| / (9.81 V): its weight in LMGC90 is then the
scene's m |g|. Dead loads other than the weight and the live load alpha x fL
are driven forces at the centre of inertia. Contacts: LMGC90's face-to-face
polyhedra contacts (PRPRx) with Coulomb friction ``IQS_CLB`` (one friction per
model: per-pair friction cannot be expressed), found once at the first step
(the wheel's detection is fixed), so a trial follows only the onset of a
collapse. Blocked dofs (a 2D scene's out-of-plane freedoms) are driven
velocities of zero; they must lie along the turned axes.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation

G_LMGC = 9.81  # m/s^2, hard-wired in the compas_lmgc90 wrapper
LETTERS = "xyzXYZ"  # blocked dofs: translations x y z, rotations X Y Z (scene axes)


def up_rotation(gravity) -> np.ndarray:
    """(3, 3) rotation Q with Q @ up = e_z, up = -gravity / |gravity| (3 or 2 components,
    a 2D gravity is padded with z = 0)."""
    g = np.zeros(3)
    g[:len(gravity)] = gravity
    up = -g / np.linalg.norm(g)
    ez = np.array([0.0, 0.0, 1.0])
    axis = np.cross(up, ez)
    s, c = np.linalg.norm(axis), float(up @ ez)
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    return Rotation.from_rotvec(axis / s * math.atan2(s, c)).as_matrix()


def outward_triangles(v: np.ndarray) -> np.ndarray:
    """(k, 3) triangles (0-based) of the convex hull of the points ``v`` (n, 3), wound
    outwards (counter-clockwise seen from outside)."""
    hull = ConvexHull(v)
    c = v.mean(axis=0)
    tris = hull.simplices.copy()
    for t in tris:
        a, b, d = v[t]
        if np.cross(b - a, d - a) @ (a - c) < 0:
            t[1], t[2] = t[2], t[1]
    return tris


class Unsupported(ValueError):
    """The scene needs what the LMGC90 wheel cannot model (the run is skipped with this reason)."""


class RigidScene:
    """The job's geometry and loads in LMGC90's frame; :meth:`trial` runs one load case."""

    @staticmethod
    def thinnest(job: dict) -> float:
        """The least bounding-box extent of the free blocks (m; every block when none is free)."""
        blocks = [b for b in job["blocks"] if not b["fixed"]] or job["blocks"]
        return min(float(np.ptp(np.vstack([q["vertices"] for q in b.get("parts", [b])]), axis=0).min())
                   for b in blocks)

    def __init__(self, job: dict, gravity, dt: float, alert_rel: float = 0.01):
        import compas_lmgc90._lmgc90 as core  # noqa: F401  (fails early when the package is missing)

        self.job, self.dt = job, float(dt)
        self.Q = up_rotation(gravity)
        g = float(job["gravity_norm"])
        self.blocks = job["blocks"]
        self.free = [i for i, b in enumerate(self.blocks) if not b["fixed"]]
        compound = [b for b in self.blocks if "parts" in b]
        if compound:
            raise Unsupported(f"block {compound[0]['id']} is compound ({len(compound[0]['parts'])} convex parts): "
                              "compas_lmgc90 0.1.11 builds one convex polyhedron per body (set_one_polyr)")
        self.verts, self.tris, self.volume, self.centroid = [], [], [], []
        for b in self.blocks:  # hulls once: every trial builds its simulation from these
            v = np.asarray(b["vertices"], dtype=float) @ self.Q.T
            tris = outward_triangles(v)
            self.verts.append(v)
            self.tris.append(tris)
            self.volume.append(float(ConvexHull(v).volume))
            self.centroid.append(_volume_centroid(v, tris))
        self.density = [round(b["mass"] * g / (G_LMGC * vol), 9) for b, vol in zip(self.blocks, self.volume)]
        self.radius = [float(np.max(np.linalg.norm(v - c, axis=1))) for v, c in zip(self.verts, self.centroid)]
        self._free_radius = np.array([self.radius[i] for i in self.free])
        lmin = min(float(np.ptp(v, axis=0).max()) for v in self.verts)
        free_v = np.vstack([self.verts[i] for i in self.free] or self.verts)
        self._size = float(np.linalg.norm(np.ptp(free_v, axis=0)))
        self.alert = alert_rel * lmin
        f0 = np.asarray(job["f0"], dtype=float).reshape(-1, 6)
        fL = np.asarray(job["fL"], dtype=float).reshape(-1, 6)
        self.f0 = {i: self._turn(f) for i, f in zip(self.free, f0)}
        self.fL = {i: self._turn(f) for i, f in zip(self.free, fL)}
        for i in self.free:  # the weight is LMGC90's gravity: keep the rest of the dead load
            self.f0[i][2] += self.blocks[i]["mass"] * g
        self.blocked = {i: self._blocked_dofs(i) for i in self.free}
        pairs = job.get("friction_pairs") or []
        mus = {float(job["friction"])} | {float(mu) for _, _, mu in pairs}
        if len(mus) > 1:
            raise Unsupported(f"LMGC90 (compas_lmgc90 0.1.11) takes one friction per model; this scene has "
                             f"{len(mus)}: {', '.join(f'{m:g}' for m in sorted(mus))}")
        self.mu = mus.pop()

    def _turn(self, f) -> np.ndarray:
        return np.concatenate([self.Q @ f[:3], self.Q @ f[3:]])

    def _blocked_dofs(self, i: int) -> list[int]:
        """LMGC90 dof numbers (1..6: Vx Vy Vz Rx Ry Rz) of block i's blocked scene dofs.

        LMGC90 drives translations in global axes but rotations in the body's inertia
        axes. A 2D scene's prisms get their out-of-plane translation blocked only: their
        loads and contacts are symmetric about the mid-plane, so they stay in it (blocking
        'rotations about x and y' in the body frame of a voussoir, whose inertia axes are
        turned, locked its in-plane rotation: the 9-voussoir arch held to 0.39 for 0.147).
        A 3D block with blocked rotations must have its inertia axes along the scene's
        (checked); :class:`Unsupported` names the block otherwise, and for a blocked axis that is not
        along a turned axis."""
        letters = self.blocks[i].get("blocked", "")
        if self.job.get("dim") == 2:
            letters = "".join(ch for ch in letters if ch.islower())
        elif any(ch.isupper() for ch in letters):
            S = _second_moment(self.verts[i], self.tris[i], self.centroid[i])
            off = np.abs(S - np.diag(np.diag(S))).max()
            if off > 1e-9 * np.abs(np.diag(S)).max():
                raise Unsupported(f"block {self.blocks[i]['id']}: blocked rotations, but its inertia axes are not "
                                 "the scene's (LMGC90 drives rotations in the body's inertia axes)")
        out = []
        for ch in letters:
            k = LETTERS.index(ch)
            axis = self.Q[:, k % 3]
            j = int(np.argmax(np.abs(axis)))
            if abs(abs(axis[j]) - 1.0) > 1e-9:
                raise Unsupported(f"block {self.blocks[i]['id']}: blocked dof {ch!r} is not along an axis once the "
                                 "scene is turned to LMGC90's vertical gravity")
            out.append(j + 1 + 3 * (k // 3))
        return sorted(set(out))

    def size(self) -> float:
        """Diagonal of the free blocks' bounding box (m)."""
        return self._size

    def build(self, alpha: float, t_load: float, t_ramp: float):
        """A fresh LMGC90 simulation (the previous one is superseded): the live load rises
        linearly from 0 at ``t_load`` to alpha x fL at ``t_load + t_ramp`` (s)."""
        from compas_lmgc90 import _lmgc90

        sim = _lmgc90.LMGC90Solver()
        sim.initialize(self.dt, 0.5, False)
        sim.add_one_tact_behav("iqsc0", "IQS_CLB", [self.mu])
        dens = sorted(set(self.density))
        names = {d: f"s{k + 1:0>4}" for k, d in enumerate(dens)}
        sim.set_materials(np.asarray(dens, dtype=float))
        sim.set_see_tables(self.alert)
        sim.set_nb_bodies(len(self.blocks))
        t_end = 1e9
        for i, b in enumerate(self.blocks):
            v = self.verts[i] - self.centroid[i]
            tris = self.tris[i]
            vdrv, fdrv = {}, {}
            if b["fixed"]:
                vdrv = {k: np.array([0.0, 0, 0, 0, 1, 0]) for k in range(1, 7)}
            else:
                vdrv = {k: np.array([0.0, 0, 0, 0, 1, 0]) for k in self.blocked[i]}
                for k in range(6):
                    if k + 1 in vdrv:  # a blocked dof takes no force
                        continue
                    dead, live = float(self.f0[i][k]), float(alpha * self.fL[i][k])
                    if abs(dead) + abs(live) > 0.0:
                        fdrv[k + 1] = np.array([[0.0, t_load, t_load + t_ramp, t_end],
                                                [dead, dead, dead + live, dead + live]])
            sim.set_one_polyr(names[self.density[i]], self.centroid[i].tolist(), (tris + 1).ravel().tolist(),
                              v.ravel().tolist(), len(vdrv), len(fdrv))
            for k, val in vdrv.items():
                sim.set_drvdof(i + 1, k, val.ravel().tolist(), True, False)
            for k, val in fdrv.items():
                sim.set_drvdof(i + 1, k, val.ravel().tolist(), False, True)
        sim.close_before_computing()
        return sim

    def trial(self, alpha: float, p: dict) -> dict:
        """One load case from rest: gravity alone for ``t_load`` s, the live load ramped to
        alpha over ``t_ramp`` s, held for ``t_hold`` s. Collapse when a free block moved
        more than ``collapse_rel`` x the scene size (translation plus rotation x its radius)
        from its start. Stable at the end of the hold, or earlier once the load has been
        held ``t_rest`` s and either no block moved faster than ``v_rest`` over the last
        ``t_rest / 2`` s, or the motion (the largest of any block from its start) has not
        grown over the last two such windows: blocks that rattle in place (the 70-stone
        Fig. 3 wall: 1e-5 m back and forth at 3e-4 m/s, the motion level flat for 0.35 s)
        never come to rest by speed, while a collapse's motion grows in every window. A
        collapse is told by its motion only: an earlier call on a block speeding up read
        the 55-voussoir double arch's slow creep as collapses, 0.092 for 0.125. Returns outcome (stable|collapse), motion (m), steps, time (s),
        rest (True when it ended at rest), settled (how: "speed" or "level", None when it did not) and
        the free blocks' (u, rotation vector) in scene axes
        at the end."""
        t_load, t_ramp, t_hold = p["t_load"], p["t_ramp"], p["t_hold"]
        sim = self.build(alpha, t_load, t_ramp)
        init = sim.get_initial_state()
        x0 = np.asarray(init.init_bodies, dtype=float)
        F0 = [np.asarray(f, dtype=float).reshape(3, 3) for f in init.init_body_frames]
        limit = p["collapse_rel"] * self.size()
        n_steps = int(math.ceil((t_load + t_ramp + t_hold) / self.dt))
        rest_from = int(math.ceil((t_load + t_ramp + p["t_rest"]) / self.dt))
        window = max(1, int(round(0.5 * p["t_rest"] / self.dt)))
        motion, steps, state, rest, marks, level = 0.0, 0, None, None, {}, []
        for steps in range(1, n_steps + 1):
            state = sim.compute_one_step()
            moves = self._move_vectors(state, x0, F0)
            motion = _fastest(moves)
            if not math.isfinite(motion):
                raise FloatingPointError(f"non-finite block position at t = {steps * self.dt:.3g} s")
            if motion > limit:
                break
            if steps % window == 0:
                marks[steps] = moves
                level.append(motion)
                before = marks.pop(steps - window, None)
                if steps >= rest_from and before is not None:
                    if _fastest(moves - before) / (window * self.dt) < p["v_rest"]:
                        rest = "speed"
                        break
                    if len(level) >= 3 and motion <= max(level[-3:-1]):
                        rest = "level"  # rattling in place: the motion has not grown over two windows
                        break
        disp = self._displacements(state, x0, F0) if state is not None else {}
        control = self._control(state, x0, F0) if state is not None else 0.0
        held = motion <= limit
        return {"alpha": alpha, "outcome": "stable" if held else "collapse", "motion": motion,
                "control": control, "steps": steps, "time": steps * self.dt, "rest": rest is not None,
                "settled": rest, "displacement": disp,
                "pair_forces": self._pair_forces(state) if held and state is not None else None}

    def _pair_forces(self, state) -> list:
        """``[[a, b, fx, fy, fz], ...]``: per pair of blocks in contact (their ids, a before b in
        the job's order) the sum over their contact points of the force on block b from block a
        (N, scene axes). The wheel's ``interaction_force_global`` of contact k is the force on the
        first body of ``interaction_bodies[k]`` (1-based) from the second, in LMGC90's turned axes."""
        sums = {}
        bodies = np.asarray(state.interaction_bodies, dtype=int).reshape(-1, 2) - 1
        forces = np.asarray(state.interaction_force_global, dtype=float).reshape(-1, 3) @ self.Q  # Q^T f per row
        for (i, j), f in zip(bodies, forces):
            if i == j:
                continue
            # the force on j from i is -f; on b from a for a < b
            key, g = ((i, j), -f) if i < j else ((j, i), f)
            sums[key] = sums.get(key, 0.0) + g
        ids = [b["id"] for b in self.blocks]
        return [[ids[a], ids[b], *map(float, v)] for (a, b), v in sorted(sums.items())]

    def _control(self, state, x0, F0) -> float:
        """Work conjugate of alpha (m), as the YADE side's: sum_i fL_i . (u_i, rotation_i)
        / sum_i (|fL_force_i| + |fL_moment_i| / R_i) over the free blocks."""
        u, r = self._moves(state, x0, F0)
        fL = np.array([self.fL[i] for i in self.free]).reshape(-1, 6)
        den = float(np.sum(np.linalg.norm(fL[:, :3], axis=1) + np.linalg.norm(fL[:, 3:], axis=1)
                           / np.maximum(self._free_radius, 1e-300)))
        return float(np.sum(fL[:, :3] * u) + np.sum(fL[:, 3:] * r)) / den if den > 0 else 0.0

    def _move_vectors(self, state, x0, F0) -> np.ndarray:
        """(n_free, 6): per free block [u (3), rotation vector x its radius (3)] (m) from the start."""
        u, r = self._moves(state, x0, F0)
        return np.hstack([u, r * self._free_radius[:, None]]) if len(self.free) else np.zeros((0, 6))

    def _moves(self, state, x0, F0):
        """(n_free, 3) translations (m) and (n_free, 3) rotation vectors (rad) from the start."""
        x = np.asarray(state.bodies, dtype=float)[self.free]
        F = np.asarray(state.body_frames, dtype=float).reshape(-1, 3, 3)[self.free]
        R = np.einsum("kji,kjl->kil", F, np.asarray(F0, dtype=float)[self.free])  # F^T F0 per block
        return x - x0[self.free], Rotation.from_matrix(R).as_rotvec() if len(R) else np.zeros((0, 3))

    def _displacements(self, state, x0, F0) -> dict:
        """{block id: motion} in scene axes (m, rad), laid out like the LP mechanism:
        [ux, uy, uz, rx, ry, rz] in 3D, [ux, uy, rz] in 2D."""
        out = {}
        for i, u, r in zip(self.free, *self._moves(state, x0, F0)):
            m = (self.Q.T @ u).tolist() + (self.Q.T @ r).tolist()
            out[str(self.blocks[i]["id"])] = [m[0], m[1], m[5]] if self.job.get("dim") == 2 else m
        return out


def _fastest(moves: np.ndarray) -> float:
    """Largest |u| + |rotation vector x radius| over the rows of an (n, 6) array (m); 0 for none."""
    return float(np.max(np.linalg.norm(moves[:, :3], axis=1) + np.linalg.norm(moves[:, 3:], axis=1), initial=0.0))


def _second_moment(v: np.ndarray, tris: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(3, 3) integral of (x - c)(x - c)^T over the convex polyhedron (m^5): a sum over the
    tetrahedra (c, a, b, d) of det/120 (a a^T + b b^T + d d^T + s s^T), s = a + b + d,
    with a, b, d relative to c."""
    S = np.zeros((3, 3))
    for a, b, d in v[tris] - c:
        det = np.dot(a, np.cross(b, d))
        s = a + b + d
        S += det / 120.0 * (np.outer(a, a) + np.outer(b, b) + np.outer(d, d) + np.outer(s, s))
    return S


def _volume_centroid(v: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """Volume centroid of the convex polyhedron with vertices ``v`` and outward triangles."""
    o = v.mean(axis=0)
    vol, acc = 0.0, np.zeros(3)
    for a, b, c in v[tris]:
        dv = np.dot(a - o, np.cross(b - o, c - o)) / 6.0
        vol += dv
        acc += dv * (o + a + b + c) / 4.0
    return acc / vol
