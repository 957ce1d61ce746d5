"""The DEM runner on the host side, with no DEM engine: bad input and bad knobs exit 2 before
an engine starts, and every engine fault -- missing, killed by a signal, hung, past its wall-clock
or CPU limit -- is a failed result naming it (fake engines: shell scripts in place of YADE). The
faults that need YADE itself (its script raising, a NaN in the simulation, a real run past its
time limit) are in tests/test_dem_yade.py."""
import json
import os
import stat
import time

import pytest

from dem_validation import run_scene
from dem_validation.runner import run_job
from scenes import builders as B

from tests.conftest import run_module, single_block_job


# ----------------------------------------------------------------------------- bad input

def test_bad_scene_exits_2_with_one_line(tmp_path, write_scene):
    data = B.single_block(2)
    data["blocks"][1]["box"]["size"] = [0.3, float("nan")]
    scene = write_scene(json.dumps(data))  # NaN in the file
    out = tmp_path / "out.json"
    proc = run_module("dem_validation", "run", scene, "--json", out)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and "non-finite" in proc.stderr
    assert not out.exists()


def test_bad_knob_exits_2(tmp_path, write_scene):
    proc = run_module("dem_validation", "run", write_scene(B.single_block(2)), "--set", "damping=3")
    assert proc.returncode == 2 and "damping" in proc.stderr and "Traceback" not in proc.stderr


# ----------------------------------------------------------------------------- engine faults

def _fake_yade(tmp_path, body):
    exe = tmp_path / "yade"
    exe.write_text("#!/bin/sh\n" + body + "\n")
    exe.chmod(exe.stat().st_mode | stat.S_IEXEC)
    return str(exe)


def test_yade_missing_is_failed(tmp_path, monkeypatch):
    dem = run_scene(B.single_block(2), yade=str(tmp_path / "no-such-yade"))
    assert dem["status"] == "failed" and "not found" in dem["reason"] and dem.get("alpha") is None
    monkeypatch.setenv("PATH", str(tmp_path))  # no yade on PATH
    monkeypatch.delenv("DEM_YADE", raising=False)
    dem = run_scene(B.single_block(2))
    assert dem["status"] == "failed" and "not found" in dem["reason"]


def test_an_engine_killed_by_a_signal_is_failed(tmp_path):
    res = run_job(single_block_job(), yade=_fake_yade(tmp_path, "kill -SEGV $$"), timeout_s=60)
    assert res["status"] == "failed" and "SIGSEGV" in res["reason"]


def test_an_engine_hung_past_the_time_limit_is_failed_and_killed(tmp_path):
    pidfile = tmp_path / "pid"
    exe = _fake_yade(tmp_path, f"echo $$ > {pidfile}; sleep 60 & wait")
    t0 = time.monotonic()
    res = run_job(single_block_job(), yade=exe, timeout_s=2)
    assert time.monotonic() - t0 < 20
    assert res["status"] == "failed" and "timed out" in res["reason"]
    pid = int(pidfile.read_text())
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)  # the whole process group is gone


def test_cpu_limit_counts_the_engines_own_cpu(tmp_path):
    """``cpu_limit_s``: an engine that computes (a busy loop) is killed once it has used the
    limit's CPU seconds, well before the wall-clock limit; one that waits uses no CPU and runs
    on until the wall-clock limit (the guard against a hung engine)."""
    exe = _fake_yade(tmp_path, "while :; do :; done")
    t0 = time.monotonic()
    res = run_job(single_block_job(), yade=exe, timeout_s=60, cpu_limit_s=2.0)
    assert time.monotonic() - t0 < 30
    assert res["status"] == "failed" and "CPU limit 2 s" in res["reason"] and res["cpu_s"] >= 2.0
    idle = _fake_yade(tmp_path, "sleep 60 & wait")
    res = run_job(single_block_job(), yade=idle, timeout_s=3, cpu_limit_s=2.0)
    assert res["status"] == "failed" and "timed out" in res["reason"] and res["cpu_s"] < 2.0


def test_an_engine_that_uses_no_cpu_is_killed_as_hung(tmp_path):
    """``hang_s``: an engine that waits (no CPU) is killed once it has used less than HANG_CPU_S of
    CPU for hang_s seconds, long before the wall-clock limit; one that computes is not (it runs on
    to its CPU limit). The computing one gets hang_s = 4 s, so that a quarter of a core (a machine
    busy with other work) is enough to count as computing, and a CPU limit above it."""
    from dem_validation import runner

    idle = _fake_yade(tmp_path, "sleep 60 & wait")
    t0 = time.monotonic()
    res = run_job(single_block_job(), yade=idle, timeout_s=60, hang_s=2.0)
    assert time.monotonic() - t0 < 30
    assert res["status"] == "failed" and res["reason"].startswith("hung") and res["cpu_s"] < runner.HANG_CPU_S
    busy = _fake_yade(tmp_path, "while :; do :; done")
    res = run_job(single_block_job(), yade=busy, timeout_s=60, hang_s=4.0, cpu_limit_s=6.0)
    assert res["status"] == "failed" and "CPU limit 6 s" in res["reason"] and res["cpu_s"] >= 6.0


def test_a_killed_run_keeps_its_progress_for_the_diagnosis(tmp_path):
    """A run killed at its limit keeps the progress records it sent: each phase's first (every
    new stiffness), the one before it (how far the phase before got) and the last ones, in order,
    so that a report can say how far it got."""
    recs = [{"phase": "stiffness", "eps": 1e-4}, {"eps": 1e-4, "alpha": 0.05, "step": 10},
            {"phase": "load", "alpha": 0.1}, {"eps": 1e-4, "alpha": 0.15, "step": 20},
            {"eps": 1e-4, "alpha": 0.2, "step": 30}, {"phase": "stiffness", "eps": 1e-5},
            {"phase": "load", "alpha": 0.3}]
    lines = "; ".join(f"echo 'DEMPROGRESS {json.dumps(r)}'" for r in recs)
    exe = _fake_yade(tmp_path, lines + "; while :; do :; done")
    res = run_job(single_block_job(), yade=exe, timeout_s=60, cpu_limit_s=1.0)
    assert res["status"] == "failed" and "CPU limit" in res["reason"]
    assert res["progress"]["last"] == recs
    assert res["progress"]["phases"] == [recs[0], recs[1], recs[2], recs[4], recs[5], recs[6]]
    from dem_validation.api import assemble
    from dem_validation.lmgc import assemble_rigid

    assert assemble(res, {})["progress"] == assemble_rigid(res)["progress"] == res["progress"]  # kept in the stage result


def test_validation_stages_limit_cpu_and_wall_clock():
    """reports.stages: the DEM and LMGC90 stages carry a CPU limit of at least DEM_CPU_LIMIT /
    LMGC_CPU_LIMIT and COST_FACTOR x the scene's measured cost, a wall-clock guard WALL_FACTOR
    times that, and a scene's meta.dem replaces either."""
    from reports import stages

    d = stages.dem_options({})
    assert (d["cpu_limit_s"], d["timeout_s"]) == (stages.DEM_CPU_LIMIT, stages.WALL_FACTOR * stages.DEM_CPU_LIMIT)
    big = stages.DEM_CPU_LIMIT  # a scene whose measured cost is the floor itself
    d = stages.dem_options({"meta": {"dem": {"cost_s": big}}})
    assert d["cpu_limit_s"] == stages.COST_FACTOR * big > stages.DEM_CPU_LIMIT
    lm = stages.lmgc_options({"meta": {"lmgc": {"cost_s": 1.0}}})
    assert lm["cpu_limit_s"] == stages.LMGC_CPU_LIMIT < lm["timeout_s"]
    own = stages.dem_options({"meta": {"dem": {"cpu_limit_s": 10.0, "timeout_s": 20.0, "cost_s": 1e4}}})
    assert (own["cpu_limit_s"], own["timeout_s"]) == (10.0, 20.0)
