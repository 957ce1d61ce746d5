"""What a long validation or report run is doing: the stages running now, how far each has got
(the engines' own progress records: YADE's eps, trial alpha and step; LMGC90's trial alpha and
outcome), and the time left, estimated from the stages' costs (scaled by the pace of the stages
finished so far on this machine) rather than from the count of stages done.

The worker side (:class:`StageProgress`) writes a stage's latest record to a file of a shared
folder; the main side (:class:`Board`) reads those files every :data:`REFRESH_S` seconds and
shows one status line. With a remote Dask scheduler the workers cannot reach the folder, and
the line shows the running stages without their records.
"""
from __future__ import annotations

import json
import os
import threading
import time
from pathlib import Path

#: seconds between two refreshes of the status line, and between two records written by a worker
REFRESH_S = 2.0
#: the finished stages' costs (s) from which their pace scales the time left
MIN_PACE_COST = 60.0


def _file(folder, stage: str, name: str) -> Path:
    return Path(folder) / f"{stage}-{name}.json"


class StageProgress:
    """The ``progress`` callback of one stage (picklable): writes the engine's latest record to
    ``path`` atomically, at most every REFRESH_S seconds (a trial's outcome always)."""

    def __init__(self, path):
        self.path = str(path)
        self.shown = 0.0
        self.started = time.time()
        self._write({})  # the stage has started on a worker

    def __call__(self, record: dict) -> None:
        now = time.monotonic()
        if "outcome" not in record and now - self.shown < REFRESH_S:
            return
        self.shown = now
        self._write(record)

    def _write(self, record: dict) -> None:
        tmp = f"{self.path}.{os.getpid()}.tmp"
        try:
            with open(tmp, "w") as f:
                json.dump({**record, "started": self.started}, f)
            os.replace(tmp, self.path)
        except OSError:  # progress is a courtesy: never a reason for a stage to fail
            pass


def record_text(rec: dict) -> str:
    """A progress record in a few words: 'eps 1e-05 alpha 0.1266 step 120k' (YADE) or
    'alpha 0.3015 collapsed' (LMGC90's trials)."""
    parts = []
    if isinstance(rec.get("eps"), (int, float)) and rec["eps"]:
        parts.append(f"eps {rec['eps']:.0e}")
    elif rec.get("phase"):
        parts.append(str(rec["phase"]))
    if isinstance(rec.get("dt"), (int, float)) and not rec.get("eps"):
        parts.append(f"dt {rec['dt']:.2g}")
    if isinstance(rec.get("alpha"), (int, float)):
        parts.append(f"alpha {rec['alpha']:.4g}")
    if rec.get("outcome"):
        parts.append(str(rec["outcome"]))
    if isinstance(rec.get("step"), (int, float)):
        s = int(rec["step"])
        parts.append(f"step {s // 1000}k" if s >= 10000 else f"step {s}")
    return " ".join(parts)


def _clock(seconds: float) -> str:
    seconds = max(int(seconds), 0)
    h, m = divmod(seconds // 60, 60)
    return f"{h}h{m:02d}" if h else f"{m}:{seconds % 60:02d}"


class Board:
    """The status line of a run: ``start``/``finish`` each stage with its expected cost (s), and
    the line is refreshed by a thread calling ``show(text)`` (e.g. a tqdm bar's
    ``set_postfix_str``) until ``close``."""

    def __init__(self, folder, slots: int, show, queued_cost: float = 0.0):
        self.folder, self.slots, self.show = folder, max(1, slots), show
        self.running: dict = {}  # (stage, name) -> (start time, cost)
        self.queued = float(queued_cost)
        self.spent = self.expected = 0.0  # finished stages: their seconds, and their costs
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._thread = threading.Thread(target=self._loop, daemon=True)
        self._thread.start()

    def start(self, stage: str, name: str, cost: float) -> None:
        with self._lock:
            self.running[(stage, name)] = (time.monotonic(), float(cost))
            self.queued = max(self.queued - float(cost), 0.0)

    def finish(self, stage: str, name: str) -> None:
        with self._lock:
            t0, cost = self.running.pop((stage, name), (None, 0.0))
            if t0 is not None:
                self.spent += time.monotonic() - t0
                self.expected += cost

    def pace(self, begun: dict | None = None) -> float:
        """Seconds this machine takes per second of cost: the finished stages' seconds over their
        costs, pooled with the running stages that have overrun their cost (``begun``: stage key ->
        seconds since its worker began it; such a stage has taken at least that long). 1 until
        stages of at least MIN_PACE_COST seconds of cost count, and never below the finished
        stages' own pace."""
        spent, expected = self.spent, self.expected
        for key, since in (begun or {}).items():
            cost = self.running.get(key, (None, 0.0))[1]
            if cost > 0 and since > cost:
                spent, expected = spent + since, expected + cost
        own = self.spent / self.expected if self.expected >= MIN_PACE_COST else 1.0
        return max(own, spent / expected) if expected >= MIN_PACE_COST else own

    def eta(self, begun: dict | None = None) -> float:
        """Seconds left: the queued stages' costs and what the running ones have left (at least a
        tenth of their cost: a stage past its estimate is not over), times :meth:`pace`, shared
        by the slots. ``begun``: as for :meth:`pace`."""
        now = time.monotonic()
        with self._lock:
            k = self.pace(begun)
            left = k * self.queued + sum(max(k * cost - (now - t0), 0.1 * k * cost)
                                         for t0, cost in self.running.values())
        return left / self.slots

    def line(self) -> str:
        now = time.monotonic()
        with self._lock:
            running = sorted(self.running.items(), key=lambda kv: kv[1][0])
        parts, waiting, begun = [], 0, {}
        for (stage, name), (t0, _) in running:
            rec = None
            if self.folder is not None:
                try:
                    rec = json.loads(_file(self.folder, stage, name).read_text())
                except (OSError, ValueError):
                    waiting += 1  # handed to the cluster, not yet begun on a worker
                    continue
            since = now - t0 if rec is None else time.time() - rec.get("started", time.time())
            begun[(stage, name)] = since
            text = record_text(rec) if rec else ""
            parts.append(f"{name} {stage} {_clock(since)}" + (f" ({text})" if text else ""))
        left = f"about {_clock(self.eta(begun))} left" + (f", {waiting} stage(s) waiting for a worker" if waiting else "")
        return f"running: {'; '.join(parts)} | {left}" if parts else left

    def _loop(self) -> None:
        while not self._stop.wait(REFRESH_S):
            try:
                self.show(self.line())
            except Exception:  # noqa: BLE001 - a status line must never stop the run
                pass

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2 * REFRESH_S)


def path_for(folder, stage: str, name: str) -> str | None:
    """The progress file of a stage in ``folder`` (None: no folder, no progress)."""
    return None if folder is None else str(_file(folder, stage, name))
