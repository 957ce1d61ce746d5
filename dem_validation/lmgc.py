"""LMGC90's ``dem`` result of one scene (rigid contacts), in the layout of
:mod:`dem_validation.api`: the engine :mod:`dem_validation.engines.lmgc90` as a dict.
"""
from __future__ import annotations

from . import engines
from .engines.lmgc90.assemble import assemble_rigid as _assemble_rigid


def run_loaded_lmgc90(scene, knobs: dict, *, timeout_s=None, progress=None, keep_dir=False,
                      interfaces=None, hint: float | None = None, cpu_limit_s=None) -> dict:
    """LMGC90 pushover of a loaded :class:`limit.model.scene.Scene`; every fault is a failed dict.
    ``hint``: a guessed alpha (the limit analysis's) to start the bracket from; it saves
    trials, it does not enter the result."""
    return engines.get("lmgc90").run(scene, knobs, timeout_s=timeout_s, progress=progress, keep_dir=keep_dir,
                                     interfaces=interfaces, hint=hint, cpu_limit_s=cpu_limit_s).to_dict()


def assemble_rigid(raw: dict) -> dict:
    """The ``dem`` dict from the LMGC90 side's result."""
    return _assemble_rigid(raw).to_dict()
