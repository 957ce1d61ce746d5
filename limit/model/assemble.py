"""From a scene to the matrices of the limit analysis problems, with their scaling.

Notation (all unscaled, SI units):

* ``u`` (n_dof,) free-block velocities (:mod:`limit.model.kinematics`),
  ``B`` (m nq, n_dof) the compatibility matrix, ``q = B u``.
* ``x`` (n_x,) interface actions of the chosen model (:mod:`limit.model.yield_domain`),
  ``r = H x`` the interface generalised stresses.
* Equilibrium: ``E x + f0 + alpha fL = 0`` with ``E = B.T H`` (= ``A.T``).
* Yield: ``Y x <= k`` (k = 0 for dry joints; cohesion and tension, :mod:`limit.model.yield_domain`). Flow: associative ``A u = -Y.T lam``, non-associative
  ``A u = G lam``, with ``A = H.T B``.

Scaling (what the solvers see): variables ``x = Dx * xh`` with each interface's
force components divided by an estimate of its normal force
(:mod:`limit.model.scaling`) and its moments by that force times the contact's half
size; every equilibrium row (``Df``) and every yield row (``Sy``) divided by
its largest coefficient after that. So neither the units, the scene's size,
the spread of forces between the top and the foot of a wall, nor a large
friction coefficient set the conditioning. Scaled quantities carry an ``h``.
``Lc`` (median free-block size, m) and ``Wc`` (mean free-block weight, N) are
the scene's characteristic length and force.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from limit.model import kinematics, loads, scaling, yield_domain
from limit.geom.interfaces import Interfaces, find_interfaces
from limit.model.pair_checks import check_friction_pairs
from limit.settings import DEFAULT as DEFAULT_SETTINGS, Settings, resolve as resolve_settings


@dataclass
class Options:
    """Modelling options. ``model``: "paper" or "vertex" interfaces; ``n_slide``:
    sliding faces per interface (3D; 4 is the paper's; None: the scene's
    ``interfaces.sliding_faces``, else :data:`DEFAULT_SLIDE_FACES`); ``slide_fit``:
    "auto" | "circumscribed" | "inscribed" (see :mod:`limit.model.yield_domain`; with
    ``n_slide`` None, the scene's ``interfaces.slide_fit`` where it gives one); ``settings``:
    route thresholds, time budgets and check tolerances (:mod:`limit.settings`), a
    :class:`limit.settings.Settings` or a mapping of the fields to change from the defaults
    (ValueError names an unknown field or a wrong type)."""

    model: str = "paper"
    n_slide: int | None = None
    slide_fit: str = "auto"
    settings: Settings = DEFAULT_SETTINGS

    def __post_init__(self):
        self.settings = resolve_settings(self.settings)


#: sliding faces of a 3D interface when neither the options nor the scene say: 24 inscribed
#: faces lie within 1 - cos(7.5 deg) = 0.86 % inside the Coulomb cone in every direction; the
#: paper's 4 circumscribed ones are exact along the interface axes but 41 % too strong at
#: 45 deg (squat block at 45 deg, mu 0.4: paper 0.566, 24 faces 0.397, LMGC90 0.400, YADE 0.401)
DEFAULT_SLIDE_FACES = 24


def friction_model(scene, options: "Options") -> tuple[int, str]:
    """(sliding faces, fit) used for ``scene``: the options', else the scene's, else the default."""
    if options.n_slide is not None:
        return int(options.n_slide), options.slide_fit
    if scene.sliding_faces is not None:
        return int(scene.sliding_faces), scene.slide_fit or "auto"
    return DEFAULT_SLIDE_FACES, options.slide_fit


@dataclass
class Assembled:
    scene: object
    I: Interfaces
    model: yield_domain.InterfaceModel
    options: Options
    B: sp.csr_matrix
    A: sp.csr_matrix          # (n_x, n_dof) = H.T B
    f0: np.ndarray            # (n_dof,)
    fL: np.ndarray            # (n_dof,)
    Lc: float
    Wc: float
    Dx: np.ndarray            # (n_x,)
    Df: np.ndarray            # (n_dof,)
    Sy: np.ndarray            # (n_faces,) yield row scale: Yh = diag(1/Sy) Y diag(Dx)
    Eh: sp.csr_matrix         # (n_dof, n_x) scaled equilibrium
    Yh: sp.csr_matrix         # (n_faces, n_x) scaled yield
    f0h: np.ndarray
    fLh: np.ndarray
    timings: dict = field(default_factory=dict)
    #: (n_free * ndof,) bool: the dofs that are unknowns (False where a block has them ``blocked``)
    keep: np.ndarray | None = None
    #: (n_faces,) scaled right-hand side of the yield rows, ``Yh xh <= kh`` (kh = k / Sy; zero
    #: for dry joints)
    kh: np.ndarray | None = None

    def __post_init__(self):
        if self.kh is None:
            self.kh = np.zeros(self.Yh.shape[0])

    @property
    def bonded(self) -> bool:
        """True when a yield row has a right-hand side (``kh`` not zero): a joint with cohesion or
        tensile strength, or a tie's capacity. The joints alone: ``I.bonded``."""
        return bool(np.any(self.kh))

    @property
    def n_dof(self) -> int:
        return self.B.shape[1]

    @cached_property
    def block_size(self) -> np.ndarray:
        """:func:`block_sizes` of the scene, kept: the lever arm that makes a moment residual a
        force (:func:`limit.solve.verify.block_equilibrium`, once per iterate at scale)."""
        return block_sizes(self.scene)

    def full(self, v) -> np.ndarray:
        """A dof vector (n_dof,) expanded to every free-block dof (n_free * ndof,), zero where blocked."""
        v = np.asarray(v, dtype=float)
        if self.keep is None or self.keep.all():
            return v
        out = np.zeros(self.keep.size)
        out[self.keep] = v
        return out


def block_sizes(scene) -> np.ndarray:
    """(n_free,) the largest extent of each free block's vertices along an axis (m), in the order
    of ``scene.free``."""
    return np.array([np.ptp(scene.blocks[i].poly.vertices, axis=0).max() for i in scene.free])


def _check_contacts(scene, I) -> None:
    """SceneError when the scene has no interface at all, naming its free blocks (nothing could
    hold them, and the problem would have no row); a loose block among touching ones is the
    LP's "infeasible", with the block named (limit.analysis)."""
    from limit.errors import SceneError

    if len(I):  # a loose block among others: the LP answers "infeasible" and names it
        return
    loose = [scene.blocks[i].id for i in scene.free]
    if loose:
        from limit.model.pair_checks import gap_phrase

        shown = ", ".join(f"'{b}'" for b in loose[:5]) + (f" and {len(loose) - 5} more" if len(loose) > 5 else "")
        raise SceneError(f"block{'s' if len(loose) > 1 else ''} {shown} touch{'es' if len(loose) == 1 else ''} "
                         f"no other block, so nothing holds {'them' if len(loose) > 1 else 'it'}: for "
                         f"'{loose[0]}', {gap_phrase(scene, int(scene.free[0]))}")


#: a tie capacity above this x the sum of the scene's load magnitudes (N) is taken as that: the
#: tie cannot yield below alpha of that order, and the solvers get a finite bound
UNBREAKABLE = 1e6


def assemble(scene, options: Options | None = None, interfaces: Interfaces | None = None) -> Assembled:
    """Build every matrix of the problem for ``scene`` (timings in ``.timings``, seconds)."""
    options = options or Options()
    t0 = time.perf_counter()
    I = find_interfaces(scene) if interfaces is None else interfaces
    _check_contacts(scene, I)
    check_friction_pairs(scene, I)
    t1 = time.perf_counter()
    B = kinematics.compatibility(scene, I)
    n_slide, fit = friction_model(scene, options)
    options = dataclasses.replace(options, n_slide=n_slide, slide_fit=yield_domain.resolve_fit(n_slide, fit))
    model = yield_domain.build(I, options.model, options.n_slide, options.slide_fit)
    f0, fL = (f.ravel() for f in loads.dead_and_live(scene))
    keep = blocked_mask(scene)
    s_k = scaling.normal_force_estimate(scene, I, f0, fL)
    if not keep.all():  # blocked dofs (rollers, symmetry planes) are no unknowns
        B, f0, fL = B[:, keep].tocsr(), f0[keep], fL[keep]
    A = (model.H.T @ B).tocsr()

    free = scene.free
    sizes = block_sizes(scene) if len(free) else np.ones(1)
    Lc = float(np.median(sizes))
    g = float(np.linalg.norm(scene.gravity))
    Wc = float(np.mean([scene.blocks[i].mass for i in free]) * g) if len(free) else 1.0
    # Variables scaled by each interface's estimated force (moments by force x half size of the contact),
    # equilibrium rows by their largest coefficient after that (see limit.model.scaling).
    half = I.l1 if scene.dim == 2 else 0.5 * np.sqrt(np.maximum(I.area, 1e-300))
    Dx = s_k[model.x_iface] * np.where(model.x_is_moment, half[model.x_iface], 1.0)
    if scene.ties:  # one tension per tie (limit.model.ties), scaled by its capacity
        from limit.model.ties import generalised_forces

        Et = generalised_forces(scene, scene.ties)[keep]
        # a capacity beyond UNBREAKABLE x the scene's whole load never binds: capped there, so
        # that no solver sees a bound of 1e300
        total = float(np.abs(f0).sum() + np.abs(fL).sum()) or 1.0
        cap = np.minimum([t.capacity for t in scene.ties], UNBREAKABLE * total)
        model = yield_domain.with_ties(model, cap)
        A = sp.vstack([A, sp.csr_matrix(Et.T)]).tocsr()
        Dx = np.concatenate([Dx, np.minimum(cap, total)])
    E = A.T.tocsr()
    E1 = (E @ sp.diags(Dx)).tocsr()
    Df = np.maximum(abs(E1).max(axis=1).toarray().ravel(), 1e-300) if E1.shape[0] else np.ones(0)
    Eh = (sp.diags(1.0 / Df) @ E1).tocsr()
    Y1 = (model.Y @ sp.diags(Dx)).tocsr()
    Sy = np.maximum(abs(Y1).max(axis=1).toarray().ravel(), 1e-300)
    Yh = (sp.diags(1.0 / Sy) @ Y1).tocsr()
    t2 = time.perf_counter()
    return Assembled(scene, I, model, options, B, A, f0, fL, Lc, Wc, Dx, Df, Sy, Eh, Yh,
                     f0 / Df, fL / Df, {"interfaces_s": t1 - t0, "assembly_s": t2 - t1}, keep, model.k / Sy)


def blocked_mask(scene) -> np.ndarray:
    """(n_free * ndof,) bool, False at the dofs the scene's blocks have ``blocked``."""
    nd = scene.ndof
    keep = np.ones(len(scene.free) * nd, dtype=bool)
    for k, i in enumerate(scene.free):
        for j in scene.blocks[i].blocked:
            keep[k * nd + j] = False
    return keep
