"""YADE side, vertex-to-face block model (the default, ``--contact vertex``).

Each block is one YADE clump of two kinds of member: its convex polyhedron
(a ``Polyhedra`` shape, which only ever meets spheres) and a sphere of radius
r inset at each vertex (tangent to, or inside, every face plane through the
vertex; a 2D scene's prism has one per polygon corner, at one height; the host
computes the centres, :mod:`dem_validation.job`).
Contacts are vertex sphere against the other block's polyhedron, all in C++
with stock classes: ``Ig2_Sphere_Polyhedra_ScGeom`` (the closest point of the
polyhedron; ``edgeCoeff = vertexCoeff = 0``, so a sphere that has slid past
the edge of a face carries nothing instead of riding a ramp-like normal: the
corner-to-face scheme of UDEC and 3DEC), ``FrictPhys`` and
``Law2_ScGeom_FrictPhys_CundallStrack(sphericalBodies=False)`` (the moments of
the contact forces about the bodies' own centres, not about a sphere centre:
the default gives wrong torques on the polyhedron). Each contact keeps its own
shear force with the Coulomb cap mu |Fn|; no Python runs during a step.
Sphere-sphere and polyhedron-polyhedron pairs are masked out of the collider.

Stiffness of a contact point: kn_point = kn * a_point (N/m), kn = rho g / eps
(N/m^3) and a_point the median interface area per contact point (m^2, from
the host); shear ks = ks_ratio * kn_point. The clump's reference point is the
block's centroid (the spheres are massless to 1e-12 of the block's mass).
"""
from __future__ import annotations

import math

from yade import (O, Vector3, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,  # noqa: F401
                  Bo1_Sphere_Aabb, InteractionLoop, Ig2_Sphere_Polyhedra_ScGeom, NewtonIntegrator,
                  Ip2_FrictMat_FrictMat_FrictPhys, Law2_ScGeom_FrictPhys_CundallStrack, FrictMat,
                  PyRunner)
from yade import utils

from yade_model import BlockModel, polyhedron_body

#: collider masks: spheres meet polyhedra only (same-mask pairs sharing a bit of AVOID are skipped)
SPHERE_MASK, POLY_MASK, AVOID = 0b011, 0b101, 0b110
#: the spheres' share of a block's mass (they only carry contacts)
SPHERE_MASS = 1e-12


class VertexModel(BlockModel):
    """Clumps of one polyhedron and its vertex spheres; ``self.bid[i]`` is block i's clump."""

    def __init__(self, job, eps):
        """The model at settlement strain ``eps``, with its own sphere radius
        r = max(floor, per_eps x eps) (``job["sphere_radius"]``)."""
        super().__init__(job)
        law = job["sphere_radius"]
        self.r = max(float(law["floor"]), float(law["per_eps"]) * float(eps))
        self.a_point = float(job["point_area"])
        self.pen_max, self.n_contacts = 0.0, 0  # largest penetration / r and loaded contacts at the last measure
        # the motion limits of the pushover scale with the softest planned run's strain: slips
        # and rearrangements under friction do not shrink with the contact stiffness
        self.detect_eps = max(float(e) for e in self.p["eps"])
        self._build()
        self.mass_factor = self.scale_masses(float(self.p["mass_quantile"]))
        self._engines()
        self.set_stiffness(float(eps))
        self.set_alpha(0.0)

    # ------------------------------------------------------------------ set-up
    def _build(self):
        job = self.job
        mu = self.friction_default
        # one FrictMat for spheres and polyhedra: PolyhedraMat has a young of its own that
        # FrictPhys does not read (it would see ElastMat's default 1e9 Pa)
        self.mat = FrictMat(young=1.0, poisson=float(self.p["ks_ratio"]), frictionAngle=math.atan(mu), density=1.0)
        O.materials.append(self.mat)
        self.radius, self.bid, self.owner = [], [], {}
        for i, blk in enumerate(job["blocks"]):
            verts = [Vector3(*v) for v in blk["vertices"]]
            members, mass = [], 0.0
            for piece in blk.get("parts", [blk]):  # a compound block: one polyhedron and its spheres per part
                poly, m = polyhedron_body(self.mat, {"id": blk["id"], **piece}, fixed=False, mask=POLY_MASK)
                members.append(poly)
                mass += m
                for v, d in zip(piece["sphere_anchors"], piece["sphere_dirs"]):
                    s = utils.sphere(Vector3(*v) + Vector3(*d) * self.r, self.r, material=self.mat, mask=SPHERE_MASK)
                    s.state.mass = SPHERE_MASS * m
                    s.state.inertia = Vector3(1, 1, 1) * (0.4 * s.state.mass * self.r ** 2)
                    members.append(s)
            cid, ids = O.bodies.appendClumped(members)
            clump = O.bodies[cid]
            # the clump's own mass properties: the block's (the spheres' share dropped)
            clump.state.mass = mass
            for k in ids:
                self.owner[k] = i
            if blk["fixed"]:
                clump.state.blockedDOFs = "xyzXYZ"
                clump.dynamic = False
            else:
                clump.state.blockedDOFs = self.blocked[i]
            self.bid.append(cid)
            c = clump.state.pos
            self.radius.append(max((v - c).norm() for v in verts))
        self.states = [O.bodies[b].state for b in self.bid]
        self._scales()

    def _engines(self):
        lmin = min(2 * self.radius[i] for i in self.free) if self.free else 1.0
        self.collider = InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Polyhedra_Aabb()], verletDist=1e-3 * lmin,
                                              avoidSelfInteractionMask=AVOID)
        self.law = Law2_ScGeom_FrictPhys_CundallStrack(sphericalBodies=False)
        self.newton = NewtonIntegrator(damping=float(self.p["damping"]), gravity=(0, 0, 0))
        engines = [
            ForceResetter(),
            self.collider,
            InteractionLoop([Ig2_Sphere_Polyhedra_ScGeom(edgeCoeff=0.0, vertexCoeff=0.0)],
                            [Ip2_FrictMat_FrictMat_FrictPhys()],
                            [self.law]),
            self.newton,
        ]
        self.bonds = list(self.job.get("bonds") or [])
        if self.bonds:  # clamps and cohesion each step, after the contacts and before the integrator
            import __main__

            self.anchor_bonds()
            __main__._dem_bonds = self.apply_bonds
            engines.insert(3, PyRunner(iterPeriod=1, command="_dem_bonds()", updateGlobals=False))
        elif self.friction:
            import __main__

            __main__._dem_pair_friction = self._pair_friction
            engines.insert(3, PyRunner(iterPeriod=1, command="_dem_pair_friction()", updateGlobals=False))
        if self.ties:  # their forces each step, after the contacts' and before the integrator
            import __main__

            self.anchor_ties()
            __main__._dem_ties = self.apply_ties
            engines.insert(len(engines) - 1, PyRunner(iterPeriod=1, command="_dem_ties()", updateGlobals=False))
        O.engines = engines

    def _pair_friction(self):
        """Per-pair friction coefficients (scene friction_pairs) on every contact."""
        own, fr = self.owner, self.friction
        for inter in O.interactions:
            if inter.isReal:
                a, b = own[inter.id1], own[inter.id2]
                mu = fr.get((a, b) if a < b else (b, a))
                if mu is not None:
                    inter.phys.tangensOfFrictionAngle = mu

    def anchor_bonds(self):
        """Each bonded joint's corners and normal in its block a's frame (called once the bodies
        are built); ``self.bond_of``: block pair -> bond."""
        self.bond_of = {}
        for b in self.bonds:
            s = O.bodies[self.bid[b["a"]]].state
            q = s.ori.conjugate()
            b["_local"] = [q * (Vector3(*p) - s.pos) for p in b["points"]]
            b["_n"] = q * Vector3(*b["normal"])
            self.bond_of[(min(b["a"], b["b"]), max(b["a"], b["b"]))] = b

    def apply_bonds(self):
        """The bonded joints for this step (``dem_validation.job.bonds``): each joint's clamp
        P = ft' A, split equally over its corners, pulls block a along the joint's normal towards
        b and b back (constant, so the joint's tension stays capped at ft' A however far it opens:
        rigid-plastic, as the limit analysis takes it); each contact of the pair gets the friction
        coefficient mu + (c' A / n) / Fn, n the pair's loaded contacts, so that its Coulomb cap is
        mu Fn + c' A / n and the joint's is mu (N + P) + c' A = mu N + c A (the contact law stays
        the stock, perfectly plastic one). Other pairs get their own mu, as
        :meth:`_pair_friction`. Fn is this step's normal force, floored at 1e-3 of the force scale."""
        own, fr, mu0 = self.owner, self.friction, self.friction_default
        forces = O.forces
        for b in self.bonds:
            if b["clamp"] <= 0.0:
                continue
            sa = O.bodies[self.bid[b["a"]]].state
            f = (sa.ori * b["_n"]) * (b["clamp"] / len(b["_local"]))
            for loc in b["_local"]:
                p = sa.pos + sa.ori * loc
                for blk, sign in ((b["a"], 1.0), (b["b"], -1.0)):
                    if not self.job["blocks"][blk]["fixed"]:
                        st = O.bodies[self.bid[blk]].state
                        forces.addF(self.bid[blk], f * sign)
                        forces.addT(self.bid[blk], (p - st.pos).cross(f * sign))
        count, live = {}, []
        for inter in O.interactions:
            if not inter.isReal:
                continue
            a, c = own[inter.id1], own[inter.id2]
            key = (a, c) if a < c else (c, a)
            live.append((inter, key))
            if key in self.bond_of and inter.phys.normalForce.norm() > 0.0:
                count[key] = count.get(key, 0) + 1
        floor = 1e-3 * self.force_scale
        for inter, key in live:
            mu = fr.get(key, mu0)
            b = self.bond_of.get(key)
            if b is not None and b["cohesion"] > 0.0 and count.get(key):
                mu += b["cohesion"] / count[key] / max(inter.phys.normalForce.norm(), floor)
            inter.phys.tangensOfFrictionAngle = mu

    def set_stiffness(self, eps):
        """Contact stiffness for settlement strain ``eps``: kn = rho g / eps (N/m^3), a point
        stiffness kn * a_point (N/m) on the materials (FrictPhys takes young * r for two equal
        materials) and on every existing contact, and the time step."""
        self.eps = float(eps)
        self.kn = self.rho_g / self.eps
        k_point = self.kn * self.a_point
        self.mat.young = k_point / self.r
        ks = float(self.p["ks_ratio"]) * k_point
        for inter in O.interactions:
            if inter.isReal:
                inter.phys.kn = k_point
                inter.phys.ks = ks
        self.dt = self.critical_time_step(max(1.0, float(self.p["ks_ratio"])) * self.kn)
        O.dt = self.dt

    def after_move(self):
        """Members follow their clump at once (YADE moves them only in the integrator,
        after the collider and the contacts of the next step)."""
        for i in self.free:
            body = O.bodies[self.bid[i]]
            st = body.state
            for k, (rel_pos, rel_ori) in body.shape.members.items():
                ms = O.bodies[k].state
                ms.pos = st.pos + st.ori * rel_pos
                ms.ori = st.ori * rel_ori
                ms.vel = Vector3(0, 0, 0)
                ms.angVel = Vector3(0, 0, 0)

    # ------------------------------------------------------------------ contacts
    def contact_memory(self):
        """Shear force of every contact (the law's memory), keyed by (sphere id, polyhedron id)."""
        return {(i.id1, i.id2): Vector3(i.phys.shearForce) for i in O.interactions if i.isReal}

    def restore_contact_memory(self, memory):
        """Contacts of the snapshot get their shear force back; others start afresh."""
        for inter in O.interactions:
            if inter.isReal:
                fs = memory.get((inter.id1, inter.id2))
                inter.phys.shearForce = Vector3(fs) if fs is not None else Vector3(0, 0, 0)

    def block_force(self, i):
        """Resultant force (N) and moment (N m, about the centroid) on block i: after a step
        the clump's entry holds its loads plus its members' contact forces (the integrator
        adds them there)."""
        cid = self.bid[i]
        return O.forces.f(cid), O.forces.t(cid)

    def contact_forces(self):
        """Per free block the sum of |normal| + |shear| force (N) of its contacts; also
        sets ``pen_max``, the largest penetration / r of any contact."""
        sums = {i: 0.0 for i in self.free}
        own = self.owner
        pen, n = 0.0, 0
        for inter in O.interactions:
            if not inter.isReal:
                continue
            f = inter.phys.normalForce.norm() + inter.phys.shearForce.norm()
            depth = inter.geom.penetrationDepth
            pen = max(pen, depth)
            n += depth > 0
            for k in (own[inter.id1], own[inter.id2]):
                if k in sums:
                    sums[k] += f
        self.pen_max, self.n_contacts = pen / self.r, n
        return sums

    def pair_forces(self):
        """``[[a, b, fx, fy, fz], ...]``: per pair of blocks in contact (their ids, a before b in
        the job's order) the sum over their contacts of the contact force on block b from block a
        (N, global axes; normal plus shear force, YADE's Law2 applying +F to the interaction's
        second body)."""
        sums = {}
        own = self.owner
        for inter in O.interactions:
            if not inter.isReal:
                continue
            i, j = own[inter.id1], own[inter.id2]
            if i == j:
                continue
            f = inter.phys.normalForce + inter.phys.shearForce  # on the body inter.id2
            key, sign = ((i, j), 1.0) if i < j else ((j, i), -1.0)
            sums[key] = sums.get(key, Vector3(0, 0, 0)) + f * sign
        ids = [b["id"] for b in self.job["blocks"]]
        return [[ids[a], ids[b], float(v[0]), float(v[1]), float(v[2])] for (a, b), v in sorted(sums.items())]

    def stats(self):
        """At the last measure (:meth:`contact_forces`, run by every residual check): how many
        contacts carry force, and the largest penetration / r."""
        return {"contacts": self.n_contacts, "penetration_ratio": self.pen_max}
