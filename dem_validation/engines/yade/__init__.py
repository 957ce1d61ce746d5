"""YADE: compliant contacts at a few stiffnesses, the collapse alpha extrapolated to rigid ones.

Host side: this adapter, :mod:`.launch` (the executable, fixed addresses) and
:mod:`.assemble` (the runs to one result), :mod:`.refine` (when a stiffer run follows). YADE side,
run by ``yade -n -x yade_main.py job.json`` in the run's work directory: :mod:`.yade_main`,
:mod:`.pushover`, :mod:`.yade_model`, :mod:`.yade_polyhedra`, :mod:`.yade_vertex`. The vertex
model runs each stiffness in a YADE process of its own (:func:`per_stiffness`). The knobs are
:data:`dem_validation.params.KNOBS`.
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
from . import refine
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
    side_files = ("yade_main.py", "pushover.py", "yade_model.py", "yade_polyhedra.py", "yade_vertex.py")
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
        go = dict(engine=self.name, yade=executable, progress=progress, keep_dir=keep_dir)
        if contact == "vertex":
            raw = per_stiffness(job, p, timeout_s=timeout_s, cpu_limit_s=cpu_limit_s, **go)
        else:
            raw = run_job(job, timeout_s=timeout_s, cpu_limit_s=cpu_limit_s, **go)
        return assemble(raw, p).with_(time_s=time.monotonic() - t0, params=used, contact=contact)

    def collapse_line(self, dem: dict) -> str:
        raw = ", ".join(_run_text(r) for r in dem["runs"])
        if len(dem["runs"]) == 1:
            how = "the one run"
        elif dem.get("extrapolation", {}).get("method") == "richardson":
            how = "rigid-contact extrapolation of the two stiffest runs"
        else:
            how = "the stiffest run (no trend with the stiffness) of the runs"
        return f"DEM collapsed: alpha = {dem['alpha']:.5g} +- {dem['alpha_uncertainty']:.2g} ({how} {raw})"


def per_stiffness(job: dict, p: dict, *, timeout_s=None, cpu_limit_s=None, **go) -> dict:
    """The vertex model's runs, one YADE process per stiffness, as one YADE-side result
    (``{"status", "runs", "length", "cpu_s", "steps_total", "refinement"}``).

    Each process builds its model from scratch. A second model built in a process that ran one
    does not repeat from process to process (docs/performance.md, 'One YADE process per
    stiffness'), so no process builds two. The planned stiffnesses ``p["eps"]`` run softest first;
    each run after a collapse starts near the softer run's bracket (``hint``), and a run that is
    not the stiffest planned when it starts has the wider ``alpha_rtol_soft``. While the two
    stiffest disagree, one more run follows (:func:`refine.next_eps`, on the CPU seconds of the
    processes so far).
    ``timeout_s`` and ``cpu_limit_s`` bound all the runs together; ``go``: :func:`run_job`'s other
    arguments. A failed run ends the sequence with its reason and the runs before it."""
    eps_list = [float(e) for e in p["eps"]]
    runs: list = []
    out = {"status": "done", "runs": runs, "cpu_s": 0.0, "steps_total": 0}
    t0 = time.monotonic()
    extra, k = 0, 0
    while k < len(eps_list):
        prev = runs[-1] if runs and runs[-1]["status"] == "collapsed" and runs[-1].get("alpha_lo") else None
        last = k == len(eps_list) - 1  # a softer run only sets the extrapolation's slope: a wider bracket will do
        one = {"eps": eps_list[k], "hint": [prev["alpha_lo"], prev["alpha_hi"]] if prev else None,
               "alpha_rtol": p["alpha_rtol"] if last else max(p["alpha_rtol"], p["alpha_rtol_soft"])}
        left = None if timeout_s is None else timeout_s - (time.monotonic() - t0)
        cpu_left = None if cpu_limit_s is None else max(cpu_limit_s - out["cpu_s"], 1e-3)
        raw = run_job(dict(job, stiffness=one), timeout_s=left, cpu_limit_s=cpu_left, **go)
        out["cpu_s"] += float(raw.get("cpu_s") or 0.0)
        out["steps_total"] += int(raw.get("steps_total") or 0)
        for key in ("length", "fixed_addresses"):
            if key in raw:
                out.setdefault(key, raw[key])
        if raw.get("status") != "done" or not raw.get("runs"):
            why = raw.get("reason", "the YADE side returned no run")
            return dict(out, status="failed", reason=f"the run at eps {eps_list[k]:g}: {why}" if runs else why,
                        **({"progress": raw["progress"]} if "progress" in raw else {}))
        runs.extend(raw["runs"])
        k += 1
        if k == len(eps_list):
            stiffer, why = refine.next_eps(runs, extra, out["cpu_s"], p)
            if why:
                out["refinement"] = why
            if stiffer is not None:  # the two stiffest runs are not yet close: one stiffer run
                eps_list.append(stiffer)
                extra += 1
    out["time_s"] = time.monotonic() - t0
    return out


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
