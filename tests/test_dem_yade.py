"""DEM pushover in YADE against closed forms, and every DEM fault reported as failed.

These tests run YADE (``make test`` installs it); they never skip. Closed forms
(rigid blocks, horizontal body force alpha x weight, friction mu):
  * one block b x h rocks at alpha = b / h when mu > b / h, slides at alpha = mu
    when mu < b / h;
  * a stack of n equal blocks b x h overturns as a whole about the base toe at
    alpha = b / (n h) when friction is high.
Tolerance 2% after the extrapolation to rigid contacts. A small running-bond
wall is checked against the project's own frictional (NLP) limit analysis
within 5%.
"""
import json
import os
import stat
import threading
import time

import pytest

from dem_validation import run_scene
from dem_validation import params as P
from dem_validation.job import build_job
from dem_validation.runner import run_job
from limit.analysis import analyse
from limit.interfaces import find_interfaces
from limit.loads import dead_and_live
from limit.scene import load_scene
from scenes import builders as B

from tests.conftest import run_module

pytestmark = pytest.mark.yade
RTOL = 0.02


def _dem(scene, **knobs):
    dem = run_scene(scene, timeout_s=900, **knobs)
    assert dem["status"] == "collapsed", dem.get("reason")
    return dem


@pytest.mark.parametrize("dim", [2, 3])
def test_single_block_rocks_at_b_over_h(dim):
    b, h = 0.3, 1.0
    dem = _dem(B.single_block(dim, b, h, mu=0.8))
    assert dem["alpha"] == pytest.approx(b / h, rel=RTOL)
    soft, stiff = (r["alpha"] for r in dem["runs"])
    assert soft < stiff < b / h  # penetrating contacts rock early; stiffer ones less so
    u = dem["displacement"]["block"]
    rz = u[2] if dim == 2 else u[4]  # 3D: rotation about y (x right, z up: toppling to +x is +ry)
    assert (rz < 0) if dim == 2 else (rz > 0)  # toppling towards +x
    assert u[0] > 0


def test_single_block_slides_at_mu_3d():
    mu = 0.4
    dem = _dem(B.single_block(3, 1.0, 1.0, mu=mu))
    assert dem["alpha"] == pytest.approx(mu, rel=RTOL)
    for r in dem["runs"]:  # sliding does not depend on the contact stiffness
        assert r["alpha"] == pytest.approx(mu, rel=RTOL)
    ux, uy, uz, rx, ry, rz = dem["displacement"]["block"]
    assert ux > 0 and abs(ry) * 1.0 < 0.1 * ux and abs(uz) < 0.1 * ux


def test_stack_of_three_overturns_at_b_over_3h():
    n, b, h = 3, 0.3, 0.5
    dem = _dem(B.stack(n, 2, b, h, mu=0.8))
    assert dem["alpha"] == pytest.approx(b / (n * h), rel=RTOL)
    rz = [dem["displacement"][f"s{k}"][2] for k in range(n)]
    assert all(r < 0 for r in rz) and max(rz) / min(rz) > 0.8  # the stack rotates as one piece


#: knobs of the wall test: the default stiffness pair, twice the (conservative) estimated
#: critical time step and a 1% bracket: 2.5 min instead of 6.5 min for the same alpha
#: (0.3562 against 0.3567 with the defaults; NLP 0.3571)
WALL_KNOBS = {"cfl": 2.0, "alpha_rtol": 0.01}


def test_running_bond_wall_3x3_against_the_nlp():
    """3 x 3 running-bond wall, L = H = 0.4, mu = 1.2. With friction (no dilatancy) the
    top corner - the end half block c1-3 with the top block c2-2 resting on it - rocks off
    as one piece about the outer toe of c1-3 while its joints with c1-2 and c2-1 open:
    alpha = 5/14. The associative LP forbids that opening-with-slip (it would need a
    dilatancy of mu) and finds 1.0. The DEM must follow the frictional physics."""
    scene = B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2)
    la = analyse(load_scene(scene), method="nlp")
    a_lp, a_nlp = la["lp"]["alpha"], la["nlp"]["alpha"]
    assert la["lp"]["status"] == "optimal" and la["nlp"]["status"] == "optimal"
    assert a_nlp < 0.5 * a_lp  # a scene where friction matters
    dem = _dem(scene, **WALL_KNOBS)
    assert abs(dem["alpha"] / a_nlp - 1.0) <= 0.05
    assert abs(dem["alpha"] / a_lp - 1.0) > 0.5  # far from the associative answer
    # the same mechanism: the blocks that turn in the NLP turn in the DEM, as one piece
    nlp_rz = {k: v[2] for k, v in la["nlp"]["mechanism"].items()}
    dem_rz = {k: v[2] for k, v in dem["displacement"].items()}
    moving = lambda rz: {k for k, r in rz.items() if abs(r) > 0.1 * max(map(abs, rz.values()))}  # noqa: E731
    assert moving(dem_rz) == moving(nlp_rz) == {"c1-3", "c2-2"}
    assert dem_rz["c1-3"] < 0 and dem_rz["c2-2"] == pytest.approx(dem_rz["c1-3"], rel=0.05)


def test_command_line_result_file_slides_2d(tmp_path, write_scene):
    mu = 0.4
    scene = write_scene(B.single_block(2, 1.0, 1.0, mu=mu, name="slider"))
    out = tmp_path / "out.json"
    proc = run_module("dem_validation", "run", scene, "--json", out, "--quiet")
    assert proc.returncode == 0, proc.stderr
    res = json.loads(out.read_text())
    assert (res["scene"], res["n_blocks"], res["n_free_blocks"], res["n_interfaces"]) == ("slider", 2, 1, 1)
    dem = res["dem"]
    assert dem["status"] == "collapsed" and dem["alpha"] == pytest.approx(mu, rel=RTOL)
    assert len(dem["displacement"]["block"]) == 3  # [ux, uy, rz]
    assert [r["eps"] for r in dem["runs"]] == sorted(P.DEFAULTS["eps"], reverse=True)
    assert dem["params"]["damping"] == P.DEFAULTS["damping"] and dem["time_s"] > 0
    hist = dem["history"]
    assert hist[0]["phase"] == "settle" and {"alpha", "outcome", "control", "eps"} <= set(hist[1])
    assert "alpha =" in proc.stdout


def test_two_runs_at_once_do_not_collide():
    scene = B.single_block(2, 1.0, 1.0, mu=0.3)
    results = [None, None]

    def go(k):
        results[k] = run_scene(scene, timeout_s=300, eps=[1e-4], alpha_rtol=0.02)

    threads = [threading.Thread(target=go, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for dem in results:
        assert dem["status"] == "collapsed" and dem["alpha"] == pytest.approx(0.3, rel=0.03)


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


# ----------------------------------------------------------------------------- DEM faults

def _job(**knobs):
    scene = load_scene(B.single_block(2, 0.3, 1.0, mu=0.8))
    f0, fL = dead_and_live(scene)
    return build_job(scene, find_interfaces(scene), f0, fL, P.check(knobs))


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


def test_yade_crash_is_failed(tmp_path):
    # a job the YADE script cannot use: YADE's Python raises, YADE exits 1
    job = _job()
    del job["blocks"][1]["vertices"]
    res = run_job(job, timeout_s=120)
    assert res["status"] == "failed" and "exited with status 1" in res["reason"] and "vertices" in res["reason"]
    # a crash by a signal
    res = run_job(job, yade=_fake_yade(tmp_path, "kill -SEGV $$"), timeout_s=60)
    assert res["status"] == "failed" and "SIGSEGV" in res["reason"]


def test_yade_hang_past_the_time_limit_is_failed_and_killed(tmp_path):
    pidfile = tmp_path / "pid"
    exe = _fake_yade(tmp_path, f"echo $$ > {pidfile}; sleep 60 & wait")
    t0 = time.monotonic()
    res = run_job(_job(), yade=exe, timeout_s=2)
    assert time.monotonic() - t0 < 20
    assert res["status"] == "failed" and "timed out" in res["reason"]
    pid = int(pidfile.read_text())
    with pytest.raises(ProcessLookupError):
        os.kill(pid, 0)  # the whole process group is gone
    # the real YADE stopped by a time limit shorter than the run
    dem = run_scene(B.stack(3, 2, 0.3, 0.5, mu=0.8), timeout_s=4)
    assert dem["status"] == "failed" and "timed out" in dem["reason"] and dem.get("alpha") is None


def test_nan_in_the_simulation_is_failed():
    job = _job()
    job["f0"][0][0] = float("nan")  # a NaN force drives the block's position to NaN
    res = run_job(job, timeout_s=120)
    assert res["status"] == "failed" and "NaN" in res["reason"]
