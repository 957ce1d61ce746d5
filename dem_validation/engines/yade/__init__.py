"""YADE: compliant contacts at a few stiffnesses, the collapse alpha extrapolated to rigid ones.

Host side: this adapter, :mod:`.launch` (the executable, fixed addresses) and
:mod:`.assemble` (the runs to one result). YADE side, run by ``yade -n -x yade_main.py
job.json`` in the run's work directory: :mod:`.yade_main`, :mod:`.pushover`,
:mod:`.refine` (when a stiffer run follows), :mod:`.yade_model`, :mod:`.yade_polyhedra`,
:mod:`.yade_vertex`. The knobs are :data:`dem_validation.params.KNOBS`.
"""
from __future__ import annotations

import os
import time
from pathlib import Path

from ... import params as P
from ...job import build_job, unmodelled
from ...runner import run_job
from .. import Models
from ..result import DemResult, failed, nothing_free, skipped
from .assemble import assemble
from .launch import find_yade, no_aslr_prefix


class Yade:
    name = "yade"
    label = "YADE"
    description = "compliant contacts extrapolated to rigid ones"
    rigid = False
    knob_table = P.KNOBS
    side_dir = Path(__file__).resolve().parent
    #: they import one another, never the project's packages; each run gets copies in its work
    #: directory, so YADE sees the same relative paths from any clone
    side_files = ("yade_main.py", "pushover.py", "refine.py", "yade_model.py", "yade_polyhedra.py", "yade_vertex.py")
    entry = "yade_main.py"

    def knobs(self, given: dict, contact: str = "vertex") -> dict:
        return P.check(given, contact)

    def models(self, contact: str = "vertex") -> Models:
        vertex = contact == "vertex"  # the vertex model bonds joints and carries ties
        return Models(ties=vertex, bonds=vertex, compound=contact != "polyhedra")  # a Polyhedra is one convex body

    def executable(self, given: str | None) -> str:
        exe = find_yade(given)
        if exe is None:
            raise LookupError(f"YADE executable not found ({given or os.environ.get('DEM_YADE') or 'yade'!r}"
                              " is not on PATH or not executable)")
        return exe

    def command(self, exe: str, entry: str) -> list:
        return no_aslr_prefix() + [exe, "-n", "-x", "-j1", "-f1", entry, "job.json"]

    def run_facts(self) -> dict:
        return {"fixed_addresses": bool(no_aslr_prefix())}

    def run(self, scene, p: dict, *, timeout_s=None, progress=None, keep_dir=False, interfaces=None,
            cpu_limit_s=None, hint=None, executable=None, contact="vertex") -> DemResult:
        """``hint`` does not apply (each stiffness brackets its own collapse)."""
        from limit.geom.interfaces import find_interfaces
        from limit.model.loads import dead_and_live

        t0 = time.monotonic()
        used = {k: (list(v) if isinstance(v, (list, tuple)) else v) for k, v in p.items()}
        if not len(scene.free):
            return nothing_free(params=used)
        models = self.models(contact)
        compound = [b.id for b in scene.blocks if b.parts]
        if compound and not models.compound:
            return failed(f"contact {contact}: one convex body per block, and block '{compound[0]}' is compound "
                          "(the vertex model, the default, clumps its parts)", time_s=0.0, params=used)
        I = find_interfaces(scene) if interfaces is None else interfaces
        why = unmodelled(I, scene, ties=models.ties, bonds=models.bonds)
        if why:
            return skipped(why, params=used)
        f0, fL = dead_and_live(scene)
        try:
            job = build_job(scene, I, f0, fL, p, contact=contact)
        except ValueError as exc:  # e.g. vertex spheres that do not fit a block at these knobs
            return failed(f"cannot build the DEM model: {exc}", time_s=time.monotonic() - t0, params=used)
        raw = run_job(job, engine=self.name, yade=executable, timeout_s=timeout_s, progress=progress,
                      keep_dir=keep_dir, cpu_limit_s=cpu_limit_s)
        return assemble(raw, p).with_(time_s=time.monotonic() - t0, params=used, contact=contact)

    def collapse_line(self, dem: dict) -> str:
        raw = ", ".join(_run_text(r) for r in dem["runs"])
        how = ("rigid-contact extrapolation of the two stiffest" if dem.get("extrapolation", {}).get("method")
               == "richardson" else "the stiffest run (no trend with the stiffness) of")
        return (f"DEM collapsed: alpha = {dem['alpha']:.5g} +- {dem['alpha_uncertainty']:.2g} "
                f"({how} runs {raw})")


def _run_text(run: dict) -> str:
    """One run of the result: its alpha (or what happened instead) and its eps."""
    if run.get("alpha") is not None:
        what = f"{run['alpha']:.5g}"
    elif run.get("dead_load_collapse"):
        what = "dead-load collapse"
    else:
        what = str(run.get("status"))
    return f"{what} (eps {run['eps']:.2g})"


ENGINE = Yade()
