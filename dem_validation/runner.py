"""Host side: run one DEM job in its engine's process (:mod:`dem_validation.engines`) and
read its result back.

Each run gets its own temporary directory (job file, result file, the engine's
stderr), its own process group, ``-j1`` (one OpenMP thread) and a wall-clock
limit, so several runs at once do not collide. Every fault ends as a result
dict with ``"status": "failed"`` and a one-line ``reason``: the engine missing,
a non-zero exit or a signal, a time-out, a CPU limit or a hang (the whole process
group is killed), a missing, unreadable or non-finite result file.
"""
from __future__ import annotations

import collections
import json
import math
import os
import queue
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from pathlib import Path

from . import engines

PROGRESS_TAG = "DEMPROGRESS "
#: an engine that has used less than HANG_CPU_S of CPU over the last HANG_S seconds of wall clock is
#: hung (a dead-locked or stopped process; a computing one, even on a crowded machine, uses far
#: more), and is killed: run_job's ``hang_s``. The wall-clock limit stays the last guard.
HANG_S = 600.0
HANG_CPU_S = 1.0
#: progress records a failed run keeps for its diagnosis (``"progress"`` of the failed result):
#: every one that starts a phase (e.g. a YADE run's new stiffness) and the one before it (the last of
#: the phase before: a killed 70-stone wall's run kept four stiffnesses but not the alpha each had
#: reached), and the last TRAIL_LAST
TRAIL_LAST = 20


class _Trail:
    """The progress records of one run worth keeping when it fails (:data:`TRAIL_LAST`)."""

    def __init__(self):
        self.phases: list[dict] = []
        self.last: collections.deque = collections.deque(maxlen=TRAIL_LAST)

    def add(self, rec: dict) -> None:
        phase = rec.get("phase") if isinstance(rec, dict) else None
        if phase is not None and (phase == "stiffness" or not self.phases or self.phases[-1].get("phase") != phase):
            if self.last and (not self.phases or self.last[-1] is not self.phases[-1]):
                self.phases.append(self.last[-1])  # how far the phase before got (e.g. its last alpha)
            self.phases.append(rec)
        self.last.append(rec)

    def dump(self) -> dict:
        return {"phases": self.phases, "last": list(self.last)}


def engine_env(exe: str, work: Path) -> dict:
    """The engine process's whole environment, the same from any shell, clone or parent
    process (with fixed addresses, a longer environment would shift YADE's heap and with it
    the order CGAL gives the polyhedra's vertices; see engines.yade.launch): one OpenMP and
    BLAS thread, a fixed hash seed (the Python side iterates in the same order), no
    display, HOME in the work directory (YADE's config files land there), no byte-code
    files (a run that reads them allocates differently from one that writes them)."""
    return {
        "PATH": os.pathsep.join(dict.fromkeys([os.path.dirname(exe), "/usr/local/bin", "/usr/bin", "/bin"])),
        "HOME": str(work), "LC_ALL": "C.UTF-8", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
        "PYTHONHASHSEED": "0", "PYTHONDONTWRITEBYTECODE": "1", "DEM_JOB": "job.json",
        # YADE's polyhedra contact copies and intersects CGAL polyhedra every step, and 43 % of
        # a step went to malloc/free (perf, 25-block wall): a larger per-thread free-list cache
        # cuts the step time by about 25 % with the same results bit for bit
        "GLIBC_TUNABLES": "glibc.malloc.tcache_count=1000",
    }


def failed(reason: str, **extra) -> dict:
    return {"status": "failed", "reason": " ".join(str(reason).split()), **extra}


def _tail(path: Path, n=400) -> str:
    """Last meaningful line of a log file (at most n characters)."""
    try:
        lines = [ln.strip() for ln in path.read_text(errors="replace").splitlines() if ln.strip()]
    except OSError:
        return ""
    return lines[-1][-n:] if lines else ""


def _finite(obj) -> bool:
    if isinstance(obj, float):
        return math.isfinite(obj)
    if isinstance(obj, dict):
        return all(_finite(v) for v in obj.values())
    if isinstance(obj, list):
        return all(_finite(v) for v in obj)
    return True


def _reader(stream, q):
    for line in iter(stream.readline, ""):
        q.put(line)
    q.put(None)


def run_job(job: dict, *, yade: str | None = None, timeout_s: float | None = None, progress=None,
            keep_dir: bool = False, script: Path | None = None, engine: str = engines.DEFAULT,
            cpu_limit_s: float | None = None, hang_s: float | None = HANG_S) -> dict:
    """Run ``job`` (see dem_validation.job) in the engine called ``engine``
    (:func:`dem_validation.engines.get`); returns the engine side's result dict or a failed
    one. ``yade``: the engine's executable (None: its default); ``script``: an entry script
    run instead of the engine's own. ``progress(dict)`` receives the
    progress records (alpha, step, ...). ``timeout_s``: wall-clock limit (None: no limit).
    ``cpu_limit_s``: limit of the engine's own CPU seconds (None: no limit), which unlike the
    wall clock does not run out on a machine busy with other work. ``hang_s``: an engine that uses
    less than HANG_CPU_S of CPU in that many seconds is killed as hung (None: never); the
    wall-clock limit is the last guard."""
    eng = engines.get(engine)
    label = eng.label
    try:
        exe = eng.executable(yade)
    except LookupError as exc:
        return failed(str(exc))
    if timeout_s is not None and timeout_s <= 0:
        return failed(f"time limit reached before {label} could start")
    work = Path(tempfile.mkdtemp(prefix="dem-"))
    t0 = time.monotonic()
    try:
        job = dict(job, result="result.json")
        (work / "job.json").write_text(json.dumps(job))
        for name in eng.side_files:
            shutil.copyfile(eng.side_dir / name, work / name)
        entry = Path(script).name if script else eng.entry
        if script:
            shutil.copyfile(script, work / entry)
        env = engine_env(exe, work)
        cmd = eng.command(exe, entry)
        with open(work / "yade.err", "w") as err:
            try:
                proc = subprocess.Popen(cmd, cwd=work, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                        stderr=err, text=True, env=env, start_new_session=True)
            except OSError as exc:
                return failed(f"cannot start {label} ({exe}): {exc.strerror or exc}")
            q: queue.Queue = queue.Queue()
            th = threading.Thread(target=_reader, args=(proc.stdout, q), daemon=True)
            th.start()
            trail = _Trail()

            def forward(rec):
                trail.add(rec)
                if progress is not None:
                    progress(rec)

            limit = _pump(proc, q, forward, t0, timeout_s, cpu_limit_s, hang_s)
            th.join(timeout=5)
        elapsed = time.monotonic() - t0
        if limit is not None:
            cpu = getattr(proc, "cpu_at_kill", None)
            extra = {"cpu_s": cpu} if cpu is not None else {}
            extra["progress"] = trail.dump()  # how far it got, for the diagnosis
            if limit == "cpu":
                return failed(f"used {cpu:.0f} s of CPU (CPU limit {cpu_limit_s:g} s) in {elapsed:.1f} s; "
                              f"{label} was killed", time_s=elapsed, **extra)
            if limit == "hung":
                return failed(f"hung: used less than {HANG_CPU_S:g} s of CPU in {hang_s:g} s of wall clock "
                              f"({elapsed:.1f} s in all); {label} was killed", time_s=elapsed, **extra)
            return failed(f"timed out after {elapsed:.1f} s (time limit {timeout_s:g} s); {label} was killed",
                          time_s=elapsed, **extra)
        rc = proc.returncode
        result_path = work / "result.json"
        if rc != 0 or not result_path.exists():
            if rc is not None and rc < 0:
                try:
                    sig = signal.Signals(-rc).name
                except ValueError:
                    sig = str(-rc)
                why = f"{label} crashed (signal {sig})"
            elif rc != 0:
                why = f"{label} exited with status {rc}"
            else:
                why = f"{label} exited without writing a result"
            last = _tail(work / "yade.err")
            return failed(why + (f": {last}" if last else ""), time_s=elapsed, progress=trail.dump())
        try:
            res = json.loads(result_path.read_text())
        except (OSError, ValueError) as exc:
            return failed(f"unreadable DEM result file: {exc}", time_s=elapsed)
        if not isinstance(res, dict) or res.get("status") not in ("done", "failed", "skipped"):
            return failed("DEM result file without a valid status", time_s=elapsed)
        if not _finite(res):
            return failed("non-finite number in the DEM result", time_s=elapsed)
        res["wall_s"] = elapsed
        res.update(eng.run_facts())
        return res
    finally:
        if keep_dir:
            print(f"DEM work directory kept: {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)


def _pump(proc, q, progress, t0, timeout_s, cpu_limit_s=None, hang_s=None) -> str | None:
    """Forward progress lines until the engine exits; the limit it was killed for ("wall",
    "cpu" or "hung", checked every 0.5 s), or None."""
    deadline = None if timeout_s is None else t0 + timeout_s
    next_cpu = time.monotonic()
    ref_t, ref_cpu = next_cpu, 0.0  # the last time the engine's CPU had advanced by HANG_CPU_S
    while True:
        now = time.monotonic()
        left = None if deadline is None else deadline - now
        if left is not None and left <= 0:
            _kill(proc)
            return "wall"
        if (cpu_limit_s is not None or hang_s is not None) and now >= next_cpu:
            next_cpu = now + 0.5
            cpu = process_cpu_s(proc.pid)
            if cpu is not None:
                if cpu_limit_s is not None and cpu >= cpu_limit_s:
                    _kill(proc)
                    return "cpu"
                if cpu - ref_cpu >= HANG_CPU_S:
                    ref_t, ref_cpu = now, cpu
                elif hang_s is not None and now - ref_t >= hang_s:
                    _kill(proc)
                    return "hung"
        try:
            line = q.get(timeout=0.5 if left is None else min(0.5, left))
        except queue.Empty:
            continue
        if line is None:  # YADE closed its stdout: wait for it to exit
            try:
                proc.wait(timeout=None if deadline is None else max(0.0, deadline - time.monotonic()))
                return None
            except subprocess.TimeoutExpired:
                _kill(proc)
                return "wall"
        if line.startswith(PROGRESS_TAG) and progress is not None:
            try:
                progress(json.loads(line[len(PROGRESS_TAG):]))
            except ValueError:
                pass


def process_cpu_s(pid: int) -> float | None:
    """CPU seconds (user + system) used so far by process ``pid`` (Linux /proc), or None."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return None


def _kill(proc):
    proc.cpu_at_kill = process_cpu_s(proc.pid)
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        pass
