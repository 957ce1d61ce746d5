"""LMGC90: rigid contacts (non-smooth contact dynamics), one run of load trials from rest.

There is no contact stiffness, so there is one run and no extrapolation; the result
has ``engine: "lmgc90"`` and ``runs[0]["eps"] = 0``. Host side: this adapter and
:mod:`.assemble`. LMGC90 side, run by ``python lmgc_main.py job.json`` in the run's
work directory: :mod:`.lmgc_main` (its knobs are :data:`.lmgc_main.KNOBS`) and
:mod:`.lmgc_model`.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

from ...job import build_job, unmodelled
from ...runner import run_job
from .. import Models
from ..result import DemResult, nothing_free, skipped
from .assemble import assemble_rigid
from .lmgc_main import KNOBS
from .lmgc_main import knobs as check_knobs


class Lmgc90:
    name = "lmgc90"
    label = "LMGC90"
    description = ("rigid contacts (non-smooth contact dynamics; --set takes its knobs: " + ", ".join(KNOBS) + ")")
    rigid = True
    knob_table = KNOBS
    side_dir = Path(__file__).resolve().parent
    #: numpy, scipy and compas_lmgc90 only
    side_files = ("lmgc_main.py", "lmgc_model.py")
    entry = "lmgc_main.py"

    def knobs(self, given: dict, contact: str = "vertex") -> dict:
        """``contact`` does not apply (one block model)."""
        return check_knobs(given)

    def models(self, contact: str = "vertex") -> Models:
        return Models()

    def executable(self, given: str | None) -> str:
        return sys.executable  # compas_lmgc90 is a package of the project's Python

    def command(self, exe: str, entry: str) -> list:
        return [exe, entry, "job.json"]

    def run_facts(self) -> dict:
        return {}

    def run(self, scene, p: dict, *, timeout_s=None, progress=None, keep_dir=False, interfaces=None,
            cpu_limit_s=None, hint=None, executable=None, contact="vertex") -> DemResult:
        """``hint``: a guessed alpha (the limit analysis's) to start the bracket from; it saves
        trials, it does not enter the result. ``executable`` and ``contact`` do not apply."""
        from limit.geom.interfaces import find_interfaces
        from limit.model.loads import dead_and_live

        t0 = time.monotonic()
        p = self.knobs(p)
        stamp = {"engine": self.name, "params": p}
        if not len(scene.free):
            return nothing_free(**stamp)
        I = find_interfaces(scene) if interfaces is None else interfaces
        models = self.models()
        why = unmodelled(I, scene, ties=models.ties, bonds=models.bonds)
        if why:
            return skipped(why, **stamp)
        f0, fL = dead_and_live(scene)
        job = build_job(scene, I, f0, fL, {}, contact="polyhedra")
        job.update(gravity=[float(x) for x in scene.gravity], rigid=p)
        if hint is not None and hint > 0:
            job["hint"] = float(hint)
        raw = run_job(job, engine=self.name, timeout_s=timeout_s, progress=progress, keep_dir=keep_dir,
                      cpu_limit_s=cpu_limit_s)
        return assemble_rigid(raw).with_(time_s=time.monotonic() - t0, **stamp)

    def collapse_line(self, dem: dict) -> str:
        return f"LMGC90 (rigid contacts) collapsed: alpha = {dem['alpha']:.5g} +- {dem['alpha_uncertainty']:.2g}"


ENGINE = Lmgc90()
