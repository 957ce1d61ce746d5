"""DEM cross-check: the same scene file run as a quasi-static pushover in a DEM engine.

Host side (this package, the project's Python): load and check the scene with
:mod:`limit`, write a plain JSON job (:mod:`.job`), run it in the engine's own
process in a private directory with a time limit (:mod:`.runner`) and return the
``dem`` result (:mod:`.api`). The engines (:mod:`.engines`: ``yade``, compliant
contacts extrapolated to rigid ones; ``lmgc90``, rigid contacts) sit behind one
interface; each is a subpackage with its host-side adapter and the scripts that
run in its process.

``run_scene(scene_or_path, engine=..., **knobs) -> dict`` is the entry point; the
knobs and their defaults are in :mod:`.params` for YADE
(:data:`.engines.lmgc90.lmgc_main.KNOBS` for LMGC90).
"""
from .api import run_scene
from .params import DEFAULTS, KNOBS

__all__ = ["run_scene", "DEFAULTS", "KNOBS"]
