"""YADE side: what every block model shares - loads, state snapshots, the motion
and out-of-balance measures the pushover (:mod:`pushover`) needs.

Runs inside YADE's own Python (``yade -n -x``): imports only the standard
library and ``yade``. SI units (m, kg, N, s, rad).

Axes: a 3D scene as given. A 2D scene (x, y) becomes prisms z in [0, t]
(t = scene thickness) with the out-of-plane freedoms (z, rx, ry) blocked.

Loads: the dead and live generalised forces of every free block (force at
its centroid and moment about it, global axes) are applied as permanent
forces F = f0 + alpha * fL on the body that carries the block's motion;
YADE's gravity is off, so masses only set the dynamics (Cundall's local
damping relaxes the motion to equilibrium).

A concrete model (:mod:`yade_polyhedra`, :mod:`yade_vertex`) builds the bodies
and engines and sets ``self.bid`` (block index -> id of the body that moves it),
``self.states``, ``self.radius`` and implements ``set_stiffness``,
``block_force`` and ``contact_forces``.
"""
from __future__ import annotations

import math

from yade import O, Vector3
from yade import polyhedra_utils


class NonFiniteState(RuntimeError):
    """A body position, rotation or force became NaN or infinite."""


def free_part(f, t, blocked: str):
    """Force and torque without their blocked components (YADE letters: x y z forces,
    X Y Z torques): what the supports of those dofs take is no out-of-balance."""
    f, t = Vector3(f), Vector3(t)
    for k, c in enumerate("xyz"):
        if c in blocked:
            f[k] = 0.0
        if c.upper() in blocked:
            t[k] = 0.0
    return f, t


def polyhedron_body(mat, blk, **kw):
    """(body, mass in kg) of the YADE ``Polyhedra`` body of a job block, its mass and inertia
    set from the block's mass (from its volume at unit density when the block has none);
    ``kw`` go to ``polyhedra_utils.polyhedra`` (fixed, mask)."""
    body = polyhedra_utils.polyhedra(mat, v=[Vector3(*v) for v in blk["vertices"]], **kw)
    vol = body.shape.GetVolume()
    if not vol > 0:
        raise ValueError(f"block {blk['id']}: YADE finds no volume")
    mass = float(blk["mass"]) if blk["mass"] > 0 else vol
    body.state.mass = mass
    body.state.inertia = body.shape.GetInertia() * (mass / vol)
    return body, mass


class BlockModel:
    """The scene in YADE plus the measures the pushover needs (shared part).

    ``job`` is the dict written by the host (see dem_validation.job).
    """

    def __init__(self, job):
        self.job = job
        p = job["params"]
        self.p = p
        self.dim = int(job["dim"])
        self.rho_g = float(job["rho_g"])
        self.area = {(min(i, j), max(i, j)): float(a) for i, j, a in job["interfaces"]}
        areas = sorted(self.area.values())
        self.area_default = areas[len(areas) // 2] if areas else 1.0
        self.friction = {(min(i, j), max(i, j)): float(mu) for i, j, mu in job["friction_pairs"]}
        self.friction_default = float(job["friction"])
        self.free = [i for i, b in enumerate(job["blocks"]) if not b["fixed"]]
        self.blocked = [b.get("blocked", "zXY" if self.dim == 2 else "") for b in job["blocks"]]
        self.f0, self.fL = {}, {}
        for i, f0, fL in zip(self.free, job["f0"], job["fL"]):
            self.f0[i] = (Vector3(*f0[:3]), Vector3(*f0[3:]))
            self.fL[i] = (Vector3(*fL[:3]), Vector3(*fL[3:]))
        self.alpha = 0.0
        self.ties = list(job.get("ties") or [])

    # ------------------------------------------------------------------ ties
    def tie_stiffness(self, tie, stiff):
        """N/m of a tie at contact stiffness ``stiff`` (N/m^3): its capacity reached at an
        elongation of eps L (eps = rho g / stiff, L the mean block size), as a contact's
        settlement, so that it turns rigid with the contacts as eps falls."""
        return float(tie["capacity"]) * stiff / (self.rho_g * self.length)

    def anchor_ties(self):
        """Each tie end in its body's frame (called once the bodies are built)."""
        for t in self.ties:
            for end, p in (("a", "pa"), ("b", "pb")):
                s = O.bodies[self.bid[t[end]]].state
                t["_local_" + end] = s.ori.conjugate() * (Vector3(*t[p]) - s.pos)
            t["_L0"] = (Vector3(*t["pb"]) - Vector3(*t["pa"])).norm()

    def apply_ties(self):
        """Add each tie's force to its two bodies for this step: T = min(max(k (l - l0) +
        prestress, 0), capacity) along the tie, pulling its ends together (elastic, then at its
        capacity; slack in compression)."""
        forces = O.forces
        for t in self.ties:
            sa, sb = O.bodies[self.bid[t["a"]]].state, O.bodies[self.bid[t["b"]]].state
            pa, pb = sa.pos + sa.ori * t["_local_a"], sb.pos + sb.ori * t["_local_b"]
            d = pb - pa
            length = d.norm()
            k = self.tie_stiffness(t, getattr(self, "kn", 0.0))
            T = min(max(k * (length - t["_L0"]) + float(t["prestress"]), 0.0),
                    float(t["capacity"]))
            if T <= 0.0 or length <= 0.0:
                continue
            f = d * (T / length)
            if not self.job["blocks"][t["a"]]["fixed"]:
                forces.addF(self.bid[t["a"]], f)
                forces.addT(self.bid[t["a"]], (pa - sa.pos).cross(f))
            if not self.job["blocks"][t["b"]]["fixed"]:
                forces.addF(self.bid[t["b"]], -f)
                forces.addT(self.bid[t["b"]], (pb - sb.pos).cross(-f))

    def _scales(self):
        """Length, size, time and force scales from the built bodies (``self.radius``)."""
        job = self.job
        sizes = [2 * self.radius[i] for i in self.free] or [1.0]
        self.length = sum(sizes) / len(sizes)  # m, mean free block size
        pts = [v for i in self.free for v in job["blocks"][i]["vertices"]] or [[0, 0, 0], [1, 1, 1]]
        extent = math.sqrt(sum((max(q[k] for q in pts) - min(q[k] for q in pts)) ** 2 for k in range(3)))
        self.size = extent  # m, bounding-box diagonal of the free blocks
        self.time_scale = math.sqrt(extent / float(job["gravity_norm"]))  # s
        loads = [self.f0[i][0].norm() for i in self.free]
        self.force_scale = (sum(loads) / len(loads)) if loads and sum(loads) > 0 else 1.0

    def _frequencies(self, stiff):
        """{free block: w^2 (1/s^2)}, a bound on its highest contact frequency for a contact
        stiffness ``stiff`` per unit area (N/m^3): w^2 = 2 k (1/m + R^2/J_min), k = stiff *
        (its contact area)."""
        contact_area = {i: 0.0 for i in self.free}
        for (i, j), a in self.area.items():
            for k in (i, j):
                if k in contact_area:
                    contact_area[k] += a
        out = {}
        for i in self.free:
            s = self.states[i]
            a = contact_area[i] or self.area_default
            jmin = min(s.inertia[0], s.inertia[1], s.inertia[2])
            if self.dim == 2:
                jmin = s.inertia[2]
            out[i] = 2.0 * stiff * a * (1.0 / s.mass + self.radius[i] ** 2 / jmin)
        for t in self.ties:  # a tie adds its spring to each free block it holds
            for i in (t["a"], t["b"]):
                if i in out:
                    s = self.states[i]
                    jmin = s.inertia[2] if self.dim == 2 else min(s.inertia[0], s.inertia[1], s.inertia[2])
                    out[i] += self.tie_stiffness(t, stiff) * (1.0 / s.mass + self.radius[i] ** 2 / jmin)
        return out

    def scale_masses(self, quantile):
        """Density scaling for a quasi-static run: every free block whose contact frequency
        is above the ``quantile`` (0..1) of all free blocks' gets its mass and inertia raised
        by the ratio, so the few smallest stones do not set the time step of the whole scene.
        The loads are forces fixed by the host (from the true masses), so the statics - and
        the collapse load - do not change; only how fast a mechanism runs away does.
        Returns the largest factor applied (1.0: none)."""
        w2 = self._frequencies(1.0)
        if not w2 or quantile >= 1.0:
            return 1.0
        ranked = sorted(w2.values())
        target = ranked[min(len(ranked) - 1, int(quantile * len(ranked)))]
        worst = 1.0
        for i, w in w2.items():
            f = w / target
            if f > 1.0:
                s = self.states[i]
                s.mass = s.mass * f
                s.inertia = s.inertia * f
                worst = max(worst, f)
        return worst

    def critical_time_step(self, stiff):
        """Critical time step estimate (s) for a contact stiffness ``stiff`` per unit area
        (N/m^3): dt = cfl * 2 / w_max over the free blocks (:meth:`_frequencies`)."""
        w2max = max(self._frequencies(stiff).values(), default=0.0)
        if not w2max > 0:
            raise ValueError("no contact stiffness: cannot choose a time step")
        return float(self.p["cfl"]) * 2.0 / math.sqrt(w2max)

    # ------------------------------------------------------------------ loads
    def set_alpha(self, alpha):
        """Apply F = f0 + alpha fL (N) and T = t0 + alpha tL (N m) to every free block."""
        forces = O.forces
        for i in self.free:
            (f0, t0), (fl, tl) = self.f0[i], self.fL[i]
            forces.setPermF(self.bid[i], f0 + fl * alpha)
            forces.setPermT(self.bid[i], t0 + tl * alpha)
        self.alpha = alpha

    # ------------------------------------------------------------------ state
    def snapshot(self):
        """Positions, orientations and the contact law's memory (velocities are dropped)."""
        return {"pos": {i: Vector3(self.states[i].pos) for i in self.free},
                "ori": {i: self.states[i].ori.normalized() for i in self.free},
                "memory": self.contact_memory(), "alpha": self.alpha, "iter": O.iter}

    def restore(self, snap, alpha=None):
        """Back to a snapshot at rest (and to its load factor unless ``alpha`` is given);
        the collider is made to re-run."""
        for i in self.free:
            s = self.states[i]
            s.pos = Vector3(snap["pos"][i])
            s.ori = snap["ori"][i]
            s.vel = Vector3(0, 0, 0)
            s.angVel = Vector3(0, 0, 0)
            # aspherical bodies (clumps, polyhedra) are integrated through their angular
            # momentum: left alone, a block restored after a collapse went on turning
            s.angMom = Vector3(0, 0, 0)
        self.after_move()
        self.restore_contact_memory(snap["memory"])
        self.collider.doSort = True
        self.collider.fastestBodyMaxDist = -1
        self.set_alpha(snap["alpha"] if alpha is None else alpha)

    def after_move(self):
        """Hook: bodies were moved by hand (clump members follow their clump)."""

    def displacements(self, ref):
        """Per free block (u (3,), rotation vector (3,)) from the snapshot ``ref`` (m, rad)."""
        out = {}
        for i in self.free:
            s = self.states[i]
            du = s.pos - ref["pos"][i]
            rot = (s.ori * ref["ori"][i].conjugate()).toRotationVector()
            out[i] = (du, rot)
        return out

    def max_motion(self, ref):
        """max over free blocks of |u| + |rotation| * R (m) since ``ref``."""
        worst = 0.0
        for i, (du, rot) in self.displacements(ref).items():
            d = du.norm() + rot.norm() * self.radius[i]
            if not math.isfinite(d):
                raise NonFiniteState(f"block {self.job['blocks'][i]['id']}: non-finite position")
            worst = max(worst, d)
        return worst

    def control_displacement(self, ref):
        """Work conjugate of alpha (m): sum_i fL_i . u_i / sum_i |fL_i| over free blocks,
        u_i = (translation, rotation * R_i) from ``ref``."""
        num = den = 0.0
        for i, (du, rot) in self.displacements(ref).items():
            fl, tl = self.fL[i]
            num += fl.dot(du) + tl.dot(rot)
            den += fl.norm() + tl.norm() / max(self.radius[i], 1e-300)
        return num / den if den > 0 else 0.0

    def residual(self):
        """Largest relative out-of-balance of any free block: max(|F| / F_ref,
        |T| / (F_ref R)) with F_ref = |f0 + alpha fL| + the sum of the block's contact
        force magnitudes (+ 1e-3 of the mean dead load, so unloaded blocks are measured
        too). Normalising by the contact forces as well as the block's own load (DEM's
        usual unbalanced-force ratio, per block) keeps a light block low in a tall wall,
        which carries many times its own weight, from holding the run on its force
        noise."""
        worst = 0.0
        floor = 1e-3 * self.force_scale
        contact = self.contact_forces()
        for i in self.free:
            f, t = free_part(*self.block_force(i), self.blocked[i])
            (f0, t0), (fl, tl) = self.f0[i], self.fL[i]
            ref = (f0 + fl * self.alpha).norm() + contact[i] + floor
            r = max(f.norm() / ref, t.norm() / (ref * self.radius[i]))
            if not math.isfinite(r):
                raise NonFiniteState(f"block {self.job['blocks'][i]['id']}: non-finite force")
            worst = max(worst, r)
        return worst

    def step(self, n):
        step = O.step
        for _ in range(n):
            step()

    def pair_forces(self):
        """Contact forces summed per pair of touching blocks, or None where the model does not
        record them: see :meth:`yade_vertex.VertexModel.pair_forces`."""
        return None

    def stats(self):
        """Contact statistics of the model (dict of numbers); none by default."""
        return {}

    def check(self):
        """Raise when the model left its range of validity; nothing by default."""
