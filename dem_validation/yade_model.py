"""YADE side: the scene as YADE bodies, the per-contact Coulomb shear law, and
the state measures the pushover (:mod:`pushover`) needs.

Runs inside YADE's own Python (``yade -n -x``): imports only the standard
library and ``yade``. SI units (m, kg, N, s, rad).

Axes: a 3D scene as given. A 2D scene (x, y) becomes prisms z in [0, t]
(t = scene thickness) with the out-of-plane freedoms (z, rx, ry) blocked.

Contacts: ``Law2_PolyhedraGeom_PolyhedraPhys_Volumetric`` gives the normal
force kn * overlap volume at the overlap's centroid (kn in N/m^3, from the
settlement strain eps: kn = rho g / eps, so a block of height h sinks eps h
under its own weight). Its own shear force is switched off (friction angle
0): YADE 2023.02a keeps one shear force shared by all interactions, so any
scene with two contacts creeps. :class:`ShearLaw` instead keeps one incremental
elastic shear force per interaction, capped at mu |Fn| (Coulomb, no cohesion,
no tension), and adds it between the interaction loop and the integrator.

Loads: the dead and live generalised forces of every free block (force at
its centroid and moment about it, global axes) are applied as permanent
forces F = f0 + alpha * fL; YADE's gravity is off, so masses only set the
dynamics (Cundall's local damping relaxes the motion to equilibrium).
"""
from __future__ import annotations

import math

from yade import (O, Vector3, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,  # noqa: F401
                  InteractionLoop, Ig2_Polyhedra_Polyhedra_PolyhedraGeom, PyRunner,
                  Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys, NewtonIntegrator,
                  Law2_PolyhedraGeom_PolyhedraPhys_Volumetric, PolyhedraMat)
from yade import polyhedra_utils


class NonFiniteState(RuntimeError):
    """A body position, rotation or force became NaN or infinite."""


def _free_part(f, t, blocked: str):
    """Force and torque without their blocked components (YADE letters: x y z forces,
    X Y Z torques): what the supports of those dofs take is no out-of-balance."""
    f, t = Vector3(f), Vector3(t)
    for k, c in enumerate("xyz"):
        if c in blocked:
            f[k] = 0.0
        if c.upper() in blocked:
            t[k] = 0.0
    return f, t


class ShearLaw:
    """Per-interaction incremental shear force with a Coulomb cap.

    ``fs[(id1, id2)]`` is the shear force on body id2 (the opposite acts on id1),
    in N, kept in the contact's tangent plane. Increment per step:
    dFs = -ks * shearInc (shearInc: relative tangential displacement of id2 with
    respect to id1 at the contact point over the step); ks = kt * A (N/m), with
    kt = ks_ratio * kn (N/m^3) and A the contact's area (m^2) found by the host
    (the median contact area for contacts the host did not list).
    """

    def __init__(self, model):
        self.model = model
        self.fs = {}
        self._ks = {}
        self._mu = {}

    def ks_mu(self, a, b):
        key = (a, b) if a < b else (b, a)
        ks = self._ks.get(key)
        if ks is None:
            m = self.model
            ks = self._ks[key] = m.kt * m.area.get(key, m.area_default)
            self._mu[key] = m.friction.get(key, m.friction_default)
        return ks, self._mu[key]

    def apply(self):
        states, forces = self.model.states, O.forces
        old, new = self.fs, {}
        for inter in O.interactions:
            if not inter.isReal:
                continue
            fn2 = inter.phys.normalForce.squaredNorm()
            if not fn2 > 0.0:
                continue  # separated: the shear force is forgotten
            a, b = inter.id1, inter.id2
            g = inter.geom
            ks, mu = self.ks_mu(a, b)
            fs = old.get((a, b))
            if fs is None:
                fs = g.shearInc * (-ks)
            else:
                n = g.normal
                fs = fs - n * fs.dot(n) - g.shearInc * ks
            cap = mu * mu * fn2
            s2 = fs.squaredNorm()
            if s2 > cap:
                fs = fs * math.sqrt(cap / s2)
            new[(a, b)] = fs
            c = g.contactPoint
            forces.addF(b, fs)
            forces.addF(a, -fs)
            forces.addT(b, (c - states[b].pos).cross(fs))
            forces.addT(a, (states[a].pos - c).cross(fs))
        self.fs = new


class Model:
    """The scene in YADE plus the measures the pushover needs.

    ``job`` is the dict written by the host (see dem_validation.job). Body ids
    equal the block indices of the scene.
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
        self.shear = ShearLaw(self)
        self._build()
        import __main__

        __main__._dem_shear_apply = self.shear.apply  # the PyRunner's command runs in __main__
        self._engines()
        self.alpha = 0.0
        self.set_stiffness(float(p["eps"][0]))
        self.set_alpha(0.0)

    # ------------------------------------------------------------------ set-up
    def _build(self):
        job = self.job
        mat = PolyhedraMat(young=2.0 * self.rho_g / float(self.p["eps"][0]), poisson=0.0, frictionAngle=0.0,
                           density=1.0)
        O.materials.append(mat)
        self.mat = mat
        self.radius = []   # m, largest centroid-vertex distance of each block
        self.f0, self.fL = {}, {}
        for i, blk in enumerate(job["blocks"]):
            verts = [Vector3(*v) for v in blk["vertices"]]
            body = polyhedra_utils.polyhedra(mat, v=verts, fixed=bool(blk["fixed"]))
            vol = body.shape.GetVolume()
            if not vol > 0:
                raise ValueError(f"block {blk['id']}: YADE finds no volume")
            mass = float(blk["mass"]) if blk["mass"] > 0 else vol
            body.state.mass = mass
            body.state.inertia = body.shape.GetInertia() * (mass / vol)
            if not blk["fixed"]:
                body.state.blockedDOFs = blk.get("blocked", "zXY" if self.dim == 2 else "")
            bid = O.bodies.append(body)
            if bid != i:
                raise RuntimeError("body ids do not follow block order")
            c = body.state.pos
            self.radius.append(max((v - c).norm() for v in verts))
        for i, f0, fL in zip(self.free, job["f0"], job["fL"]):
            self.f0[i] = (Vector3(*f0[:3]), Vector3(*f0[3:]))
            self.fL[i] = (Vector3(*fL[:3]), Vector3(*fL[3:]))
        self.states = [b.state for b in O.bodies]
        sizes = [2 * self.radius[i] for i in self.free] or [1.0]
        self.length = sum(sizes) / len(sizes)  # m, mean free block size
        pts = [v for i in self.free for v in job["blocks"][i]["vertices"]] or [[0, 0, 0], [1, 1, 1]]
        extent = math.sqrt(sum((max(q[k] for q in pts) - min(q[k] for q in pts)) ** 2 for k in range(3)))
        self.size = extent  # m, bounding-box diagonal of the free blocks
        self.time_scale = math.sqrt(extent / float(job["gravity_norm"]))  # s
        loads = [self.f0[i][0].norm() for i in self.free]
        self.force_scale = (sum(loads) / len(loads)) if loads and sum(loads) > 0 else 1.0

    def set_stiffness(self, eps):
        """Contact stiffness for settlement strain ``eps``: kn = rho g / eps (N/m^3) on the
        material and on every existing interaction, kt = ks_ratio kn, and the time step."""
        self.eps = float(eps)
        self.kn = self.rho_g / self.eps
        self.kt = float(self.p["ks_ratio"]) * self.kn
        self.mat.young = 2.0 * self.kn  # the Ip2 functor takes the harmonic mean: kn = young / 2
        for inter in O.interactions:
            if inter.isReal:
                inter.phys.kn = self.kn
        self.shear._ks.clear()
        self.dt = self._time_step()
        O.dt = self.dt

    def _time_step(self):
        """Critical time step estimate (s): per free block a bound on its highest
        contact frequency, w^2 = 2 k (1/m + R^2/J_min), k = kn * (its contact area)
        * max(1, ks_ratio); dt = cfl * 2 / w_max."""
        contact_area = {i: 0.0 for i in self.free}
        for (i, j), a in self.area.items():
            for k in (i, j):
                if k in contact_area:
                    contact_area[k] += a
        stiff = max(1.0, float(self.p["ks_ratio"])) * self.kn
        w2max = 0.0
        for i in self.free:
            s = self.states[i]
            a = contact_area[i] or self.area_default
            jmin = min(s.inertia[0], s.inertia[1], s.inertia[2])
            if self.dim == 2:
                jmin = s.inertia[2]
            w2 = 2.0 * stiff * a * (1.0 / s.mass + self.radius[i] ** 2 / jmin)
            w2max = max(w2max, w2)
        if not w2max > 0:
            raise ValueError("no contact stiffness: cannot choose a time step")
        return float(self.p["cfl"]) * 2.0 / math.sqrt(w2max)

    def _engines(self):
        lmin = min(2 * self.radius[i] for i in self.free) if self.free else 1.0
        self.collider = InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=1e-3 * lmin)
        self.newton = NewtonIntegrator(damping=float(self.p["damping"]), gravity=(0, 0, 0))
        O.engines = [
            ForceResetter(),
            self.collider,
            InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
                            [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                            [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),
            # updateGlobals=False: the command is already in __main__; the default refreshes the
            # globals on every call (a few % of a step)
            PyRunner(iterPeriod=1, command="_dem_shear_apply()", updateGlobals=False),
            self.newton,
        ]

    # ------------------------------------------------------------------ loads
    def set_alpha(self, alpha):
        """Apply F = f0 + alpha fL (N) and T = t0 + alpha tL (N m) to every free block."""
        forces = O.forces
        for i in self.free:
            (f0, t0), (fl, tl) = self.f0[i], self.fL[i]
            forces.setPermF(i, f0 + fl * alpha)
            forces.setPermT(i, t0 + tl * alpha)
        self.alpha = alpha

    # ------------------------------------------------------------------ state
    def snapshot(self):
        """Positions, orientations and shear forces (velocities are dropped)."""
        return {"pos": {i: Vector3(self.states[i].pos) for i in self.free},
                "ori": {i: self.states[i].ori.normalized() for i in self.free},
                "fs": dict(self.shear.fs), "alpha": self.alpha, "iter": O.iter}

    def restore(self, snap, alpha=None):
        """Back to a snapshot at rest (and to its load factor unless ``alpha`` is given);
        the collider is made to re-run."""
        for i in self.free:
            s = self.states[i]
            s.pos = Vector3(snap["pos"][i])
            s.ori = snap["ori"][i]
            s.vel = Vector3(0, 0, 0)
            s.angVel = Vector3(0, 0, 0)
        self.shear.fs = dict(snap["fs"])
        self.collider.doSort = True
        self.collider.fastestBodyMaxDist = -1
        self.set_alpha(snap["alpha"] if alpha is None else alpha)

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

    def contact_force_sums(self):
        """Per free block the sum of |normal| + |shear| force (N) of its contacts."""
        sums = {i: 0.0 for i in self.free}
        fs = self.shear.fs
        for inter in O.interactions:
            if not inter.isReal:
                continue
            a, b = inter.id1, inter.id2
            f = inter.phys.normalForce.norm()
            s = fs.get((a, b))
            if s is not None:
                f += s.norm()
            if a in sums:
                sums[a] += f
            if b in sums:
                sums[b] += f
        return sums

    def residual(self):
        """Largest relative out-of-balance of any free block: max(|F| / F_ref,
        |T| / (F_ref R)) with F_ref = |f0 + alpha fL| + the sum of the block's contact
        force magnitudes (+ 1e-3 of the mean dead load, so unloaded blocks are measured
        too). Normalising by the contact forces as well as the block's own load (DEM's
        usual unbalanced-force ratio, per block) keeps a light block low in a tall wall,
        which carries many times its own weight, from holding the run on its force
        noise: its own-load ratio stalled at 3-8e-3 in a settled 12-course wall while
        the contact-force ratio was 1-3e-4."""
        forces = O.forces
        worst = 0.0
        floor = 1e-3 * self.force_scale
        contact = self.contact_force_sums()
        for i in self.free:
            f, t = _free_part(forces.f(i), forces.t(i), self.job["blocks"][i].get("blocked", "zXY" if self.dim == 2 else ""))
            (f0, t0), (fl, tl) = self.f0[i], self.fL[i]
            ref = (f0 + fl * self.alpha).norm() + contact[i] + floor
            rf = f.norm() / ref
            rt = t.norm() / (ref * self.radius[i])
            r = max(rf, rt)
            if not math.isfinite(r):
                raise NonFiniteState(f"block {self.job['blocks'][i]['id']}: non-finite force")
            worst = max(worst, r)
        return worst

    def step(self, n):
        step = O.step
        for _ in range(n):
            step()
