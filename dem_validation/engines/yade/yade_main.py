"""YADE entry script: ``yade -n -x yade_main.py JOB.json``.

Reads the job file written by the host (dem_validation.job), builds the model,
runs the pushover (the vertex model: at one stiffness, ``job["stiffness"]``; Polyhedra: at each
of ``params["eps"]``) and writes
``job["result"]`` (JSON through a temporary file and a rename):
``{"status": "done"|"failed", "runs": [per stiffness], "reason", "time_s"}``. Progress goes to
stdout as lines ``DEMPROGRESS {json}``. Exit status 0 when a result file was
written (its status may be "failed", e.g. for a NaN), 3 when the job file
cannot be read; any exception escaping gives YADE's own exit status 1.
"""
import json
import math
import os
import sys
import time

# Under the yade launcher __file__ is the launcher; sys.argv[0] is this script.
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))

import pushover  # noqa: E402  (a sibling module, importable without the project's packages)
import yade_model  # noqa: E402


def run_pushovers(job, eps_list, p):
    """(model, runs): the pushover at the job's stiffnesses, each run with its ``cpu_s``.
    Polyhedra (``contact: polyhedra``): one model, a stiffer run restarts from a softer run's
    equilibrium. Vertex model (the default): one stiffness per process, ``job["stiffness"]``
    (``eps``, the softer run's bracket ``hint`` or None, and its ``alpha_rtol``; default: the first
    of ``eps_list``, no hint), in a model loaded from scratch whose first load step goes near the
    hint. The host starts one process per stiffness and decides on a stiffer run
    (:func:`refine.next_eps`): a second model built in a process that ran one does not repeat from
    process to process."""
    contact = job.get("contact", "vertex")
    if contact == "polyhedra":
        import yade_polyhedra

        model = yade_polyhedra.PolyhedraModel(job)
        emit({"phase": "start", "blocks": len(model.free), "eps": eps_list})
        return model, pushover.pushover(model, eps_list, p, emit=emit)
    if contact != "vertex":
        raise ValueError(f"unknown contact model {contact!r}")
    import yade_vertex

    one = job.get("stiffness") or {"eps": eps_list[0]}
    eps = float(one["eps"])
    model = yade_vertex.VertexModel(job, eps)
    emit({"phase": "start", "blocks": len(model.free), "eps": [eps], "sphere_radius": model.r})
    hint = tuple(one["hint"]) if one.get("hint") else None
    pk = dict(p, alpha_rtol=float(one["alpha_rtol"])) if one.get("alpha_rtol") else p
    c0 = time.process_time()
    run = pushover.pushover(model, [eps], pk, emit=emit, hint=hint)[0]
    run["cpu_s"] = time.process_time() - c0
    run["sphere_radius"] = model.r
    run["mass_factor"] = model.mass_factor
    return model, [run]


def _vec(v):
    return [float(v[0]), float(v[1]), float(v[2])]


def _layout(dim, du, rot):
    """[ux, uy, rz] in 2D, [ux, uy, uz, rx, ry, rz] in 3D (m, rad)."""
    if dim == 2:
        return [float(du[0]), float(du[1]), float(rot[2])]
    return _vec(du) + _vec(rot)


def _finite(obj):
    if isinstance(obj, float):
        return math.isfinite(obj)
    if isinstance(obj, dict):
        return all(_finite(v) for v in obj.values())
    if isinstance(obj, list):
        return all(_finite(v) for v in obj)
    return True


def write_result(path, result):
    tmp = path + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(result, fh)
    os.replace(tmp, path)


def emit(info):
    print("DEMPROGRESS " + json.dumps(info), flush=True)


def main(argv):
    job_path = argv[1] if len(argv) > 1 else os.environ.get("DEM_JOB", "")
    try:
        with open(job_path) as fh:
            job = json.load(fh)
        out = os.path.join(os.path.dirname(os.path.abspath(job_path)), job["result"])
    except (OSError, ValueError, KeyError) as exc:
        print(f"cannot read the job file {job_path!r}: {exc}", file=sys.stderr)
        return 3
    t0 = time.time()
    p = dict(job["params"])
    eps_list = [float(e) for e in p["eps"]]
    res = {"status": "failed", "runs": []}
    try:
        model, runs = run_pushovers(job, eps_list, p)
        res.update(length=model.length)
        ids = [b["id"] for b in job["blocks"]]
        for r in runs:
            c = r.pop("collapse")
            r["displacement"] = None if c is None else {
                ids[i]: _layout(model.dim, du, rot) for i, (du, rot) in c.items()}
            hp = r.pop("held_pose", None)
            if hp is not None:
                r["held_pose"] = {ids[i]: _layout(model.dim, du, rot) for i, (du, rot) in hp.items()}
        res.update(status="done", runs=runs)
        if not _finite(res):
            res = {"status": "failed", "reason": "non-finite number in the DEM result", "runs": []}
    except yade_model.NonFiniteState as exc:
        res.update(status="failed", reason=f"NaN/Inf in the DEM state at step {yade_model.O.iter}: {exc}")
    res["time_s"] = time.time() - t0
    res["cpu_s"] = time.process_time()  # CPU seconds of the YADE process: comparable under load
    res["steps_total"] = sum(int(r.get("steps", 0)) for r in res["runs"]) or int(yade_model.O.iter)
    write_result(out, res)
    return 0


rc = main(sys.argv)
sys.stdout.flush()
sys.stderr.flush()
os._exit(rc)
