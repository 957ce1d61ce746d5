"""YADE side, Polyhedra block model (``--contact polyhedra``): each block one
YADE ``Polyhedra`` body.

Contacts: ``Law2_PolyhedraGeom_PolyhedraPhys_Volumetric`` gives the normal
force kn * overlap volume at the overlap's centroid (kn in N/m^3, from the
settlement strain eps: kn = rho g / eps, so a block of height h sinks eps h
under its own weight). Its own shear force is switched off (friction angle
0): YADE 2023.02a keeps one shear force shared by all interactions, so any
scene with two contacts creeps. :class:`ShearLaw` instead keeps one incremental
elastic shear force per interaction, capped at mu |Fn| (Coulomb, no cohesion,
no tension), and adds it between the interaction loop and the integrator.
Each contact costs a copy and an intersection of two CGAL polyhedra per step.
"""
from __future__ import annotations

import math

from yade import (O, Vector3, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,  # noqa: F401
                  InteractionLoop, Ig2_Polyhedra_Polyhedra_PolyhedraGeom, PyRunner,
                  Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys, NewtonIntegrator,
                  Law2_PolyhedraGeom_PolyhedraPhys_Volumetric, PolyhedraMat)
from yade_model import BlockModel, polyhedron_body

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


class PolyhedraModel(BlockModel):
    """Polyhedra bodies; body ids equal the block indices of the scene."""

    def __init__(self, job):
        super().__init__(job)
        self.shear = ShearLaw(self)
        self._build()
        import __main__

        __main__._dem_shear_apply = self.shear.apply  # the PyRunner's command runs in __main__
        self._engines()
        self.set_stiffness(float(self.p["eps"][0]))
        self.set_alpha(0.0)

    # ------------------------------------------------------------------ set-up
    def _build(self):
        job = self.job
        mat = PolyhedraMat(young=2.0 * self.rho_g / float(self.p["eps"][0]), poisson=0.0, frictionAngle=0.0,
                           density=1.0)
        O.materials.append(mat)
        self.mat = mat
        self.radius = []   # m, largest centroid-vertex distance of each block
        for i, blk in enumerate(job["blocks"]):
            verts = [Vector3(*v) for v in blk["vertices"]]
            body, _ = polyhedron_body(mat, blk, fixed=bool(blk["fixed"]))
            if not blk["fixed"]:
                body.state.blockedDOFs = self.blocked[i]
            bid = O.bodies.append(body)
            if bid != i:
                raise RuntimeError("body ids do not follow block order")
            c = body.state.pos
            self.radius.append(max((v - c).norm() for v in verts))
        self.bid = list(range(len(job["blocks"])))
        self.states = [b.state for b in O.bodies]
        self._scales()

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
        self.dt = self.critical_time_step(max(1.0, float(self.p["ks_ratio"])) * self.kn)
        O.dt = self.dt

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

    # ------------------------------------------------------------------ contacts
    def contact_memory(self):
        return dict(self.shear.fs)

    def restore_contact_memory(self, memory):
        self.shear.fs = dict(memory)

    def block_force(self, i):
        """Resultant force (N) and moment (N m, about the centroid) on block i."""
        return O.forces.f(i), O.forces.t(i)

    def contact_forces(self):
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
