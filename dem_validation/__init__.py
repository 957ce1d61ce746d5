"""DEM cross-check: the same scene file run as a YADE quasi-static pushover.

Host side (this package, the project's Python): load and check the scene with
:mod:`limit`, write a plain JSON job (:mod:`.job`), run ``yade -n -x
yade_main.py job.json`` in a private directory with a time limit
(:mod:`.runner`), extrapolate alpha to rigid contacts (:mod:`.extrapolate`)
and return the ``dem`` result (:mod:`.api`). YADE side (YADE's own Python):
:mod:`.yade_main`, :mod:`.yade_model`, :mod:`.pushover`.

A second engine, LMGC90 (rigid contacts; ``run_scene(..., engine="lmgc90")``):
host side :mod:`.lmgc`, LMGC90 side :mod:`.lmgc_main` and :mod:`.lmgc_model`.

``run_scene(scene_or_path, **knobs) -> dict`` is the entry point; the knobs
and their defaults are in :mod:`.params` (:data:`.lmgc_main.KNOBS` for LMGC90).
"""
from .api import run_scene
from .params import DEFAULTS, KNOBS

__all__ = ["run_scene", "DEFAULTS", "KNOBS"]
