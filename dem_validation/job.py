"""Host side: the plain JSON job that the YADE script reads.

Everything YADE needs is computed here with :mod:`limit` (validated scene,
loads, interfaces), so the YADE side needs no project package:

* ``blocks``: per block ``id``, ``fixed``, ``mass`` (kg) and ``vertices``
  (world coordinates, m, always 3D: a 2D polygon becomes the prism z in [0, t]); a
  compound block also has ``parts``, per convex part its ``vertices`` and ``mass`` (kg, the
  block's mass shared by volume), and its ``vertices`` are the envelope's (the hull of all).
* ``f0``, ``fL``: per free block (scene order) the dead and live generalised
  force ``[Fx, Fy, Fz, Mx, My, Mz]`` at its centroid in global axes (N, N m),
  from :func:`limit.model.loads.dead_and_live` (2D ``[Fx, Fy, Mz]`` padded with zeros).
* ``interfaces``: ``[i, j, area]`` (m^2, 2D: length x thickness) of every
  contact found by :func:`limit.geom.interfaces.find_interfaces`;
  ``friction`` (default mu) and ``friction_pairs`` ``[i, j, mu]`` (overrides).
* ``rho_g`` (N/m^3): rho |g| with rho the mass-weighted mean density of the
  free blocks; the YADE side sets the volumetric normal stiffness
  kn = rho_g / eps (N/m^3) for each settlement strain eps of ``params["eps"]``.
* ``params``: the pushover knobs (dem_validation.params).
* ``contact``: the block model, ``vertex`` (default) or ``polyhedra``. The
  vertex model also gets ``sphere_radius``: ``{"floor": m, "per_eps": m}``,
  r(eps) = max(floor, per_eps x eps) for a run at settlement strain eps
  (:func:`sphere_radius`), ``point_area`` (m^2, the median interface area per
  contact point: a 2D interface, a segment times the thickness, has 2
  points, a 3D one as many as its polygon) and per block ``sphere_anchors``
  (m) and ``sphere_dirs``, the inset vectors d (sphere centre anchor + r d,
  :func:`dem_validation.vertex_spheres.inset_directions`).
"""
from __future__ import annotations

import numpy as np


def prism_vertices(poly2d: np.ndarray, thickness: float) -> np.ndarray:
    """(k, 2) polygon -> (2k, 3) prism vertices, z in [0, thickness]."""
    k = len(poly2d)
    z0 = np.zeros((k, 1))
    return np.vstack([np.hstack([poly2d, z0]), np.hstack([poly2d, z0 + thickness])])


#: a 2D scene's vertex spheres sit at z = MIDPLANE x thickness, one per polygon corner: half the
#: spheres of one per prism corner (the out-of-plane dofs are blocked, so the height does not
#: matter to the statics). Not 1/2: the rectangle faces of the prisms are triangulated, and at
#: mid-height a diagonal crosses the middle of the face, where the corner of a block in running
#: bond sits (YADE's closest-point search would call that an edge contact and drop it).
MIDPLANE = 0.6180339887


def sphere_anchors(vertices: np.ndarray, dirs: np.ndarray, dim: int, thickness: float):
    """(anchors (m, 3) in m, inset vectors (m, 3)) of a block's vertex spheres, from its (k, 3)
    vertices and their inset vectors (:func:`dem_validation.vertex_spheres.inset_directions`).
    3D: one per vertex. 2D (a prism from :func:`prism_vertices`): one per polygon corner at
    z = MIDPLANE x thickness, inset in the plane only (the inset's z part, off the end face,
    dropped: its in-plane part comes from the two side faces alone)."""
    if dim == 3:
        return vertices, dirs
    k = len(vertices) // 2
    anchors = vertices[:k].copy()
    anchors[:, 2] = MIDPLANE * thickness
    d = dirs[:k].copy()
    d[:, 2] = 0.0
    return anchors, d


def pad6(gen: np.ndarray, dim: int) -> np.ndarray:
    """(n, 3) 2D generalised forces [Fx, Fy, Mz] -> (n, 6); 3D arrays unchanged."""
    if dim == 3:
        return np.asarray(gen, dtype=float)
    g = np.asarray(gen, dtype=float)
    out = np.zeros((len(g), 6))
    out[:, 0:2] = g[:, 0:2]
    out[:, 5] = g[:, 2]
    return out


def rho_g(scene) -> float:
    """rho |g| (N/m^3) of the free blocks (mass-weighted mean density); kn = rho_g / eps."""
    free = [b for b in scene.blocks if not b.fixed] or scene.blocks
    rho = sum(b.mass for b in free) / sum(b.volume for b in free)
    return rho * float(np.linalg.norm(scene.gravity))


def yade_blocked(dim: int, blocked) -> str:
    """YADE's ``blockedDOFs`` letters (x y z translations, X Y Z rotations) of a block's
    blocked dofs (indices into 2D [x, y, rz] or 3D [x, y, z, rx, ry, rz]); a 2D scene's
    prisms also have z, X, Y blocked."""
    letters = ("x", "y", "Z") if dim == 2 else ("x", "y", "z", "X", "Y", "Z")
    out = "".join(letters[j] for j in blocked)
    return out + ("zXY" if dim == 2 else "")


CONTACTS = ("vertex", "polyhedra")


def sphere_radius(blocks_vertices, r_rel: float, point_force: float, rho_g: float, a_point: float,
                  pen_target: float) -> dict:
    """Vertex sphere radius law r(eps) = max(floor, per_eps x eps) (m): the floor is
    ``r_rel`` x Lmin (Lmin: the smallest block's largest extent among the blocks given as
    (k, 3) vertex arrays, m); above it, r is the radius at which the expected largest point
    force ``point_force`` (N) penetrates ``pen_target`` x r into a contact of stiffness
    k_point = rho_g / eps x a_point (N/m): per_eps = point_force / (rho_g a_point pen_target)."""
    lmin = min(float(np.ptp(v, axis=0).max()) for v in blocks_vertices)
    return {"floor": r_rel * lmin, "per_eps": point_force / (rho_g * a_point * pen_target)}


def radius_at(law: dict, eps: float) -> float:
    """r (m) of the law of :func:`sphere_radius` at settlement strain eps."""
    return max(law["floor"], law["per_eps"] * eps)


def expected_point_force(scene, interfaces, f0, fL) -> float:
    """Largest expected force on one contact point (N): the largest interface normal force
    estimated by carrying every block's dead plus live load down to its supports
    (:func:`limit.model.scaling.normal_force_estimate`), over the points of a hinge: at a hinge
    an interface's force sits on the two points of its hinge edge in 3D, on one point in 2D
    (one sphere per corner, :func:`sphere_anchors`)."""
    from limit.model.scaling import normal_force_estimate

    if not len(interfaces):
        return 0.0
    n = normal_force_estimate(scene, interfaces, np.ravel(f0), np.ravel(fL))
    return (0.5 if scene.dim == 3 else 1.0) * float(np.max(n))


def point_area(interfaces, dim: int) -> float:
    """Median interface area per contact point (m^2); 1.0 without interfaces."""
    if not len(interfaces):
        return 1.0
    npts = [2 if dim == 2 else len(poly) for poly in interfaces.polygons]
    return float(np.median(np.asarray(interfaces.area, dtype=float) / np.asarray(npts, dtype=float)))


def build_job(scene, interfaces, f0, fL, params: dict, result="result.json", contact="vertex") -> dict:
    """The job dict for one YADE run (all the stiffnesses of ``params["eps"]``)."""
    if contact not in CONTACTS:
        raise ValueError(f"contact: expected one of {', '.join(CONTACTS)}, got {contact!r}")
    def world(poly):
        v = np.asarray(poly.vertices, dtype=float)
        return prism_vertices(v, scene.thickness) if scene.dim == 2 else v

    blocks = []
    for b in scene.blocks:
        blocks.append({"id": b.id, "fixed": bool(b.fixed), "mass": float(b.mass), "vertices": world(b.poly).tolist(),
                       "blocked": yade_blocked(scene.dim, b.blocked)})
        if b.parts:
            total = sum(p.measure for p in b.parts)
            blocks[-1]["parts"] = [{"vertices": world(p).tolist(), "mass": float(b.mass * p.measure / total)}
                                   for p in b.parts]
    extra = {}
    if contact == "vertex":
        from .vertex_spheres import inset_directions

        verts = [np.asarray(b["vertices"]) for b in blocks]
        up = -np.pad(np.asarray(scene.gravity, dtype=float), (0, 3 - scene.dim))
        a_point = point_area(interfaces, scene.dim)
        force = expected_point_force(scene, interfaces, f0, fL)
        law = sphere_radius([verts[i] for i in scene.free] or verts, float(params["vertex_r"]), force, rho_g(scene),
                            a_point, float(params["pen_target"]))
        r_max = radius_at(law, max(params["eps"]))
        for b in blocks:
            for piece in b.get("parts", [b]):  # a compound block: spheres at each part's vertices
                v = np.asarray(piece["vertices"])
                try:
                    d = inset_directions(v, up, r_max)
                except ValueError as exc:
                    raise ValueError(f"block {b['id']}: {exc}") from None
                anchors, d = sphere_anchors(v, d, scene.dim, float(scene.thickness))
                piece["sphere_anchors"], piece["sphere_dirs"] = anchors.tolist(), d.tolist()
        extra = {"sphere_radius": law, "point_area": a_point}
    return {
        "format": "dem-job/1",
        "contact": contact,
        **extra,
        "name": scene.name,
        "dim": scene.dim,
        "thickness": float(scene.thickness),
        "blocks": blocks,
        "f0": pad6(f0, scene.dim).tolist(),
        "fL": pad6(fL, scene.dim).tolist(),
        "interfaces": [[int(a), int(b), float(s)] for a, b, s in zip(interfaces.a, interfaces.b, interfaces.area)],
        "friction": float(scene.friction),
        "friction_pairs": _friction_pairs(scene, interfaces),
        "ties": _ties(scene),
        "bonds": bonds(scene, interfaces),
        "rho_g": rho_g(scene),
        "gravity_norm": float(np.linalg.norm(scene.gravity)),
        "params": dict(params),
        "result": result,
    }


def _ties(scene) -> list:
    """The scene's tie rods for YADE: ``[{"a", "b" (block indices), "pa", "pb" (m, 3D; a 2D scene's at
    half its thickness), "capacity", "prestress" (N)}]``."""
    def pt(p):
        p = [float(x) for x in p]
        return p + [0.5 * float(scene.thickness)] if scene.dim == 2 else p

    return [{"id": t.id, "a": int(t.a), "b": int(t.b), "pa": pt(t.pa), "pb": pt(t.pb), "capacity": float(t.capacity),
             "prestress": float(t.prestress)} for t in getattr(scene, "ties", ())]


def bonds(scene, interfaces) -> list:
    """The bonded joints for YADE's vertex model: ``[{"a", "b" (block indices), "normal" (3,
    unit, out of a), "points" (k, 3) m (the joint polygon's corners; a 2D joint's two ends at half
    the thickness), "clamp" (N, over the whole joint), "cohesion" (N, over the whole joint)}]``.

    A joint of area A with cohesion c, tensile strength ft and friction mu (the limit analysis's
    vertex model, :mod:`limit.model.yield_domain`) has N >= -ft' A, ft' = min(ft, c / mu), and
    |V| <= mu N + c A. A dry contact pressed by an extra force P = ft' A (``clamp``, pulling the
    blocks together at the corners) carries N + P >= 0 and |V| <= mu (N + P) + c' A with c' = c - mu
    ft' (``cohesion``): the same domain (``yade_vertex.VertexModel.apply_bonds``)."""
    out = []
    from limit.solve.radenkovic import potential_interfaces

    inner = potential_interfaces(interfaces)  # c' and ft', as the lower bound takes them
    for k in np.flatnonzero((interfaces.cohesion > 0) | (interfaces.tensile > 0)):
        A = float(interfaces.area[k])
        pts = np.asarray(interfaces.polygons[k], dtype=float)
        if scene.dim == 2:
            pts = np.column_stack([pts, np.full(len(pts), 0.5 * float(scene.thickness))])
        out.append({"a": int(interfaces.a[k]), "b": int(interfaces.b[k]),
                    "normal": np.pad(np.asarray(interfaces.normal[k], dtype=float), (0, 3 - scene.dim)).tolist(),
                    "points": pts.tolist(), "clamp": float(inner.tensile[k]) * A,
                    "cohesion": float(inner.cohesion[k]) * A})
    return out


def _friction_pairs(scene, interfaces) -> list:
    """[[i, j, mu]] of the block pairs whose joints do not have the scene's friction: the
    ``interfaces.friction`` pairs and the ``joints`` groups, as the interfaces carry them."""
    pairs = {(min(i, j), max(i, j)): mu for (i, j), mu in scene.friction_pairs.items()}
    for a, b, mu in zip(interfaces.a, interfaces.b, interfaces.mu):
        if float(mu) != float(scene.friction) or (min(a, b), max(a, b)) in pairs:
            pairs[(int(min(a, b)), int(max(a, b)))] = float(mu)
    return [[int(i), int(j), float(mu)] for (i, j), mu in sorted(pairs.items())]


def unmodelled(interfaces, scene=None, ties: bool = False, bonds: bool = False) -> str | None:
    """Why an engine cannot run a scene with these interfaces (None: it can): joints with cohesion
    or tensile strength (the scene's ``joints`` groups) only where the engine has them (``bonds``:
    YADE's vertex model, :func:`bonds`), tie rods (its ``ties``) likewise (``ties``); crushing
    nowhere. The run is skipped with this reason."""
    if scene is not None and getattr(scene, "ties", ()) and not ties:
        return (f"{len(scene.ties)} tie(s); this engine models blocks and dry joints, not tie rods (YADE's vertex "
                "model does), so the dynamic check does not run here")
    fc = getattr(interfaces, "fc", None)
    if fc is not None and np.any(fc > 0):
        return (f"{int((fc > 0).sum())} joint(s) have a compressive strength fc; crushing has no rigid-block DEM "
                "(the blocks and contacts of both engines do not crush), so the dynamic check does not run")
    if getattr(interfaces, "bonded", False) and not bonds:
        n = int(((interfaces.cohesion > 0) | (interfaces.tensile > 0)).sum())
        return (f"{n} joint(s) have cohesion or tensile strength; this engine's contacts are dry Coulomb "
                "friction (YADE's vertex model bonds them), so the dynamic check does not run here")
    return None

