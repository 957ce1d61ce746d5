"""Shared helpers for the benchmarks: output folder, repeated timing, machine facts."""
from __future__ import annotations

import os
import platform
import statistics
import time
from pathlib import Path

OUT = Path(__file__).resolve().parent / "out"


def out_dir() -> Path:
    OUT.mkdir(parents=True, exist_ok=True)
    return OUT


def timed(fn, repeat=3):
    """(median seconds, last result) of ``repeat`` calls of fn()."""
    times, res = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), res


def machine() -> dict:
    return {"python": platform.python_version(), "cpus": os.cpu_count(), "machine": platform.machine()}
