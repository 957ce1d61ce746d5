"""``run_scene``: the DEM pushover of one scene, as the ``dem`` part of a result
file (docs/formats.md, 'Result file').

The ``dem`` dict:

* ``status``: ``collapsed`` | ``stable`` (no collapse up to ``alpha_max``, or
  nothing can move) | ``failed`` (with ``reason``: the engine missing, crashed,
  timed out, NaN, inconsistent runs).
* ``alpha``: the load factor extrapolated to rigid contacts (null unless
  collapsed); ``alpha_uncertainty``: worst-case effect of the bisection
  brackets on it.
* ``runs``: per contact stiffness (softest first) ``eps``, ``kn`` (N/m^3),
  ``status``, raw ``alpha`` (bracket midpoint), ``alpha_lo``, ``alpha_hi``,
  ``steps``, ``dt`` (s); ``extrapolation``: the Richardson fit
  (:mod:`dem_validation.extrapolate`).
* ``displacement``: per free block id, its motion over the collapse at the
  stiffest contacts (from the last equilibrium to where the collapse was
  detected), laid out like the LP mechanism: ``[ux, uy, rz]`` in 2D,
  ``[ux, uy, uz, rx, ry, rz]`` in 3D (m, rad; global axes, rotations
  counter-clockwise / right-handed positive).
* ``history``: every load step (``eps``, ``phase``, ``alpha``, ``outcome``,
  ``why``, ``steps``, ``residual``, ``motion`` m, ``control`` m: the live-load
  work-conjugate displacement from the settled state) - the load-displacement
  history.
* ``time_s`` (wall clock, s), ``steps``, ``params`` (every knob used).
"""
from __future__ import annotations

from . import engines
from .engines.yade.assemble import assemble as _assemble


def run_scene(scene_or_path, *, timeout_s: float | None = 1800.0, progress=None, yade: str | None = None,
              keep_dir: bool = False, contact: str = "vertex", engine: str = engines.DEFAULT,
              cpu_limit_s: float | None = None, **knobs) -> dict:
    """DEM pushover of a scene (a :class:`limit.model.scene.Scene`, a scene dict or a path).

    ``engine``: one of :func:`dem_validation.engines.names`: ``yade`` (compliant contacts,
    extrapolated to rigid ones; the default) or ``lmgc90`` (rigid contacts, non-smooth
    contact dynamics, whose knobs are :data:`dem_validation.engines.lmgc90.lmgc_main.KNOBS`;
    ``contact`` and ``yade`` do not apply).

    ``knobs``: see the engine's ``knob_table`` (:data:`dem_validation.params.KNOBS` for YADE;
    ValueError for an unknown or bad one). ``timeout_s``: wall-clock limit of the run (None: none);
    ``cpu_limit_s``: limit of the engine's CPU seconds (None: none), which a busy machine does not use up.
    ``progress(dict)``: called with progress records (eps, alpha, step, residual).
    ``yade``: the YADE executable (default $DEM_YADE or ``yade`` on PATH).
    ``contact``: the block model, ``vertex`` (vertex spheres against faces, the
    default) or ``polyhedra`` (YADE's Polyhedra, 10-25x slower).
    Raises :class:`limit.errors.SceneError` for a rejected scene; every DEM fault
    is returned as ``{"status": "failed", "reason": ...}``.
    """
    from limit.model.scene import Scene, load_scene

    eng = engines.get(engine)
    p = eng.knobs(knobs, contact)  # bad knobs before the scene
    scene = scene_or_path if isinstance(scene_or_path, Scene) else load_scene(scene_or_path)
    return eng.run(scene, p, timeout_s=timeout_s, progress=progress, executable=yade, keep_dir=keep_dir,
                   contact=contact, cpu_limit_s=cpu_limit_s).to_dict()


def run_loaded(scene, p: dict, *, timeout_s=None, progress=None, yade=None, keep_dir=False, interfaces=None,
               contact="vertex", cpu_limit_s=None) -> dict:
    """YADE's run_scene for a loaded scene and checked knobs ``p``."""
    return engines.get("yade").run(scene, p, timeout_s=timeout_s, progress=progress, executable=yade,
                                   keep_dir=keep_dir, interfaces=interfaces, contact=contact,
                                   cpu_limit_s=cpu_limit_s).to_dict()


def assemble(raw: dict, p: dict) -> dict:
    """The ``dem`` dict from the YADE side's result."""
    return _assemble(raw, p).to_dict()
