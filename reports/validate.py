"""``make validate``: every catalog scene through the limit analysis and the DEM, then the report.

Stages run in parallel through Dask: a local cluster with one single-threaded
worker process per core by default, or an existing scheduler given by
``--scheduler ADDRESS`` (or $DASK_SCHEDULER_ADDRESS), so the same command
scales to a cluster (workers receive the scene content, not paths). Results
are cached by scene content and code version (:mod:`reports.cache`): an
unchanged scene is not recomputed, an interrupted run resumes, and every result
is written atomically as soon as it arrives; a failed stage is reported but not
cached, so the next run tries it again (it is kept whole, with its histories,
under the cache's failed/ folder for diagnosis). The results table goes to
``reports/out/results.csv`` and ``.parquet``, the report to
``reports/out/index.html`` and ``index.md``. The exit status is 1 when any stage failed
(each is listed at the end), 0 otherwise.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

from .cache import DEFAULT_DIR, Cache, key
from .stages import STAGES, guess_from

OUT = Path(__file__).resolve().parent / "out"


def plan(files, stages, cache: Cache, fresh: bool, lmgc_all: bool = False):
    """(done, todo): cached results and the (stage, name, key, data, options) still to run."""
    done, todo = {}, []
    for path in files:
        data = json.loads(Path(path).read_text())
        name = data.get("name", Path(path).stem)
        for stage in stages:
            opts_fn, _ = STAGES[stage]
            opts = opts_fn(data, budget_s=None) if stage == "lmgc" and lmgc_all else opts_fn(data)
            k = key(stage, data, opts)
            hit = None if fresh else cache.get(stage, name, k)
            if hit is None and stage == "lmgc" and not opts["run"] and not fresh:
                full = opts_fn(data, budget_s=None)  # left out for its cost: a result of --lmgc-all is shown
                if full["run"]:
                    hit = cache.get(stage, name, key(stage, data, full))
            if hit is not None:
                done[(name, stage)] = hit
            else:
                todo.append((stage, name, k, data, opts))
    return done, todo


def _parts(stage: str, res: dict) -> list[dict]:
    """The parts of a stage result that carry a status: the DEM result, or the LP and NLP parts."""
    return [res] if stage in ("dem", "lmgc", "sweep") else [res.get("lp") or {}, res.get("nlp") or {}]  # la, cone


def _failed(stage: str, res: dict) -> bool:
    return any(p.get("status") == "failed" for p in _parts(stage, res))


def _reason(stage: str, res: dict) -> str:
    why = [str(p["reason"]) for p in _parts(stage, res) if p.get("status") == "failed" and p.get("reason")]
    return "; ".join(why) or "no reason given"


def dem_cost(data: dict) -> float:
    """Rough relative cost of a scene's DEM stage: its vertex spheres (the corners of the free
    blocks: a 2D polygon's, a 3D polyhedron's, 4 or 8 for a box). The longest stages are
    started first, so the short ones fill the cores at the end (counting 3D blocks three
    times put the 70-stone Fig. 3 wall, 12 minutes, behind six shorter 3D scenes)."""
    box = 4 if data.get("dim") == 2 else 8
    return float(sum(len(b["vertices"]) if "vertices" in b else box
                     for b in data.get("blocks", []) if not b.get("fixed")))


#: CPU seconds per vertex sphere of an unmeasured DEM stage: the median of cost_s / :func:`dem_cost`
#: over the catalog scenes with a measured cost (YADE 16 scenes, quartiles 0.27-1.1; LMGC90 14
#: scenes, quartiles 0.11-0.24)
DEM_S_PER_SPHERE = {"dem": 0.45, "lmgc": 0.14}


def stage_cost(stage: str, data: dict) -> float:
    """Expected CPU seconds of a stage: the measured ``meta.<stage>.cost_s`` of the scene where
    scenes/catalog.py recorded one (``dem``: YADE, ``lmgc``: LMGC90), else an estimate from
    its size (the DEM's vertex spheres x :data:`DEM_S_PER_SPHERE`; a limit analysis 0.1 s per
    free block in 2D, 0.5 s in 3D). Measured costs matter: size alone ranks a small but slow scene
    (the 17-block Fig. 5) late, and it then ends the run after everything else."""
    cost = ((data.get("meta") or {}).get(stage) or {}).get("cost_s")
    if cost is not None:
        return float(cost)
    if stage in ("dem", "lmgc"):
        return DEM_S_PER_SPHERE[stage] * dem_cost(data)
    n_free = sum(1 for b in data.get("blocks", []) if not b.get("fixed"))
    return (0.1 if data.get("dim") == 2 else 0.5) * n_free


def _run_task(stage, data, opts, la=None, progress_file=None):
    """One stage; ``la``: the scene's ``la`` result, whose alpha is the LMGC90 search's guess;
    ``progress_file``: where the engine's latest progress record goes (:mod:`reports.progress`)."""
    if la is not None:
        opts = {**opts, "hint": guess_from(la)}
    if progress_file is not None:
        from .progress import StageProgress

        record = StageProgress(progress_file)  # says the stage has begun
        if stage in ("dem", "lmgc"):
            opts = {**opts, "progress": record}
    return STAGES[stage][1](data, opts)


def execute(todo, cache: Cache, jobs: int | None, scheduler: str | None, progress=True,
            known: dict | None = None, log: str = "validate") -> dict:
    """Run the stages through Dask; store each result in the cache as it arrives. A scene's
    LMGC90 stage takes its first guess from the scene's ``la`` result: a cached one in
    ``known`` ((name, stage) -> result), else it waits for that stage (started at once if
    not yet)."""
    results = {}
    if not todo:
        return results
    known = known or {}
    from dask.distributed import as_completed
    from tqdm import tqdm

    from limit.dask_pool import dask_client

    import tempfile

    from . import progress as prog

    # the engines' progress records go through files: only where the workers share this machine
    folder = tempfile.TemporaryDirectory(prefix="validate-progress-") if scheduler is None else None
    with dask_client(jobs, scheduler) as client:
        futures = {}
        # Longest first, over every stage, the short ones filling the cores at the end. Stages are
        # handed over one per free worker thread, in this order: Dask's own priorities left the
        # 5-minute Fig. 5 and fountain YADE stages to start 20 minutes in (tasks go straight to a
        # worker unless Dask deems them root-ish), and the run ended 2 minutes later than its CPU
        # time allows.
        queue = sorted(todo, key=lambda t: -stage_cost(t[0], t[3]))
        slots = max(1, sum(client.nthreads().values()))
        la_futures = {}

        def submit(task, ac, la=None):
            stage, name, k, data, opts = task
            f = client.submit(_run_task, stage, data, opts, la,
                              prog.path_for(folder and folder.name, stage, name), key=f"{stage}-{name}-{k}", pure=False)
            futures[f] = (stage, name, k)
            board.start(stage, name, stage_cost(stage, data))
            if stage == "la":
                la_futures[name] = f
            if ac is not None:
                ac.add(f)
            return f

        def submit_next(ac=None):
            if not queue:
                return
            task = queue.pop(0)
            stage, name = task[0], task[1]
            if stage != "lmgc" or not task[4].get("run"):
                submit(task, ac)
                return
            la = known.get((name, "la"))
            if la is not None:
                submit(task, ac, la={"lp": la.get("lp"), "nlp": la.get("nlp")})
                return
            if name not in la_futures:
                own = next((t for t in queue if t[0] == "la" and t[1] == name), None)
                if own is None:  # no la stage in this run: the LMGC90 stage makes its own guess
                    submit(task, ac)
                    return
                queue.remove(own)
                submit(own, ac)
            submit(task, ac, la=la_futures[name])

        bar = tqdm(total=len(todo), unit="stage", disable=not progress, file=sys.stderr,
                   bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}] {postfix}")
        board = prog.Board(folder and folder.name, slots, bar.set_postfix_str if progress else (lambda _: None),
                           queued_cost=sum(stage_cost(t[0], t[3]) for t in queue))
        for _ in range(slots):
            submit_next()
        ac = as_completed(list(futures))
        for f in ac:
            stage, name, k = futures[f]
            board.finish(stage, name)
            submit_next(ac)
            try:
                res = f.result()
            except Exception as exc:  # a worker lost: recorded as a failure, the run goes on
                res = {"status": "failed", "alpha": None, "reason": f"worker error: {type(exc).__name__}: {exc}"}
                if stage in ("la", "cone"):
                    res = {"lp": res}
            if not _failed(stage, res):  # failures are not cached: the next run tries them again
                cache.put(stage, name, k, res)
            else:  # ... but kept whole for diagnosis
                try:
                    kept = f"full result: {cache.put_failed(stage, name, k, res)}"
                except OSError as exc:  # a diagnostic copy must not stop the run
                    kept = f"full result not kept: {exc}"
                tqdm.write(f"{log}: {name} {stage} failed: {_reason(stage, res)} ({kept})", file=sys.stderr)
            results[(name, stage)] = res
            status = _parts(stage, res)[0].get("status")
            if progress:
                tqdm.write(f"{log}: done {name} {stage}: {status}"
                           + (f" alpha {_alpha(stage, res):.4g}" if _alpha(stage, res) is not None else ""),
                           file=sys.stderr)
            bar.set_postfix_str(board.line())
            bar.update(1)
        board.close()
        bar.close()
    if folder is not None:
        folder.cleanup()
    return results


def _alpha(stage: str, res: dict):
    """The stage's headline alpha: the engine's, or step 2's (the LP's where step 2 has none)."""
    for part in (_parts(stage, res)[::-1] if stage in ("la", "cone") else _parts(stage, res)):
        if isinstance(part.get("alpha"), (int, float)):
            return float(part["alpha"])
    return None


def main(argv=None) -> int:
    from scenes.catalog import catalog_files

    ap = argparse.ArgumentParser(prog="python -m reports.validate", description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(OUT), help="report folder (default reports/out)")
    ap.add_argument("--cache", default=str(DEFAULT_DIR), help="result cache folder (default .cache/results)")
    ap.add_argument("--jobs", type=int, default=None, help="local worker processes (default: one per core)")
    ap.add_argument("--scheduler", default=os.environ.get("DASK_SCHEDULER_ADDRESS"),
                    help="address of an existing Dask scheduler (default: a local cluster)")
    ap.add_argument("--only", nargs="*", help="run only these scene names")
    ap.add_argument("--no-dem", action="store_true", help="skip the DEM stages (YADE and LMGC90)")
    ap.add_argument("--no-lmgc", action="store_true", help="skip the LMGC90 stage (rigid contacts)")
    ap.add_argument("--lmgc-all", action="store_true",
                    help="run LMGC90 on every scene (default: those whose measured cost meta.lmgc.cost_s is at "
                         "most reports.stages.LMGC_BUDGET_S)")
    ap.add_argument("--fresh", action="store_true", help="ignore cached results")
    ap.add_argument("--no-progress", action="store_true")
    args = ap.parse_args(argv)

    files = catalog_files()
    if args.only:
        files = [f for f in files if f.stem in set(args.only)]
        missing = set(args.only) - {f.stem for f in files}
        if missing:
            print(f"error: unknown scene(s): {', '.join(sorted(missing))}", file=sys.stderr)
            return 2
    stages = ["la", "cone", "sweep"] + ([] if args.no_dem else ["dem"] + ([] if args.no_lmgc else ["lmgc"]))
    t0 = time.perf_counter()
    try:
        done, df = collect(files, stages, Cache(args.cache), fresh=args.fresh, jobs=args.jobs,
                           scheduler=args.scheduler, progress=not args.no_progress, lmgc_all=args.lmgc_all)
    except KeyboardInterrupt:
        print("validate: interrupted; finished stages are cached, rerun to resume", file=sys.stderr)
        return 130
    from . import render, table

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    table.write(df, out)
    (out / "engines.md").write_text(table.engines_markdown(df))  # LA against YADE against LMGC90
    render.report(df, files, done, out, wall_time=time.perf_counter() - t0)
    bad = failures(done)  # one source for the summary and the exit status: every stage, LMGC90 too
    print(f"validate: report {out / 'index.html'} ({len(df)} scenes, {len({n for n, _, _ in bad})} with a failed "
          f"stage, {len(bad)} failed stages, {time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    for name, stage, why in bad:
        print(f"validate: FAILED {name} {stage}: {why}", file=sys.stderr)
    return 1 if bad else 0


def collect(files, stages, cache: Cache, *, fresh: bool = False, jobs: int | None = None,
            scheduler: str | None = None, progress: bool = True, lmgc_all: bool = False, log: str = "validate",
            scenes: dict | None = None):
    """(done, df): every stage result of the scene ``files`` ({(scene, stage): result}, from the
    cache or run now through :func:`execute`), the DEM starts of the contradictions
    (:mod:`reports.dem_starts`) and the results table (:func:`reports.table.results_table`).
    ``stages``: names of :data:`reports.stages.STAGES`; the DEM columns are filled for the
    engines among them; ``scenes``: {name: loaded scene} of those the caller has loaded. Raises
    KeyboardInterrupt as it comes (finished stages are cached)."""
    from . import dem_starts, table

    done, todo = plan(files, stages, cache, fresh, lmgc_all=lmgc_all)
    print(f"{log}: {len(files)} scene(s), {len(done)} stage results cached, {len(todo)} to run", file=sys.stderr)
    done.update(execute(todo, cache, jobs, scheduler, progress=progress, known=done, log=log))
    with_dem, with_lmgc = "dem" in stages, "lmgc" in stages
    starts = dem_starts.run(files, done, progress=progress) if with_dem or with_lmgc else {}
    df = table.results_table(files, done, with_dem=with_dem, with_lmgc=with_lmgc, dem_start=starts, scenes=scenes)
    return done, df


def failures(done: dict) -> list[tuple[str, str, str]]:
    """(scene, stage, reason) of every stage result in ``done`` ({(scene, stage): result}) with a
    failed part, sorted: any makes ``make validate`` exit with status 1 (the report is written
    all the same; a rerun tries only these again, the others come from the cache)."""
    return sorted((name, stage, _reason(stage, res)) for (name, stage), res in done.items() if _failed(stage, res))


if __name__ == "__main__":
    sys.exit(main())
