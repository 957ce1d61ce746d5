"""DEM pushover in YADE against closed forms, and YADE's own faults reported as failed (the
runner's handling of bad input and of a missing, crashing or hung engine, with no YADE:
tests/test_dem_runner.py).

These tests run YADE (``make test`` installs it); they never skip. They use the
default vertex-to-face block model unless they say otherwise. Closed forms
(rigid blocks, horizontal body force alpha x weight, friction mu):
  * one block b x h rocks at alpha = b / h when mu > b / h, slides at alpha = mu
    when mu < b / h;
  * a stack of n equal blocks b x h overturns as a whole about the base toe at
    alpha = b / (n h) when friction is high;
  * a portal (two columns b x h under a lintel) sways at alpha = b / h;
  * a 3D block under a horizontal load at an angle topples about the base edge
    that gives the least b_e / ((h/2) d . n_e) (scenes/catalog.py);
  * a squat block twisted by a couple about the vertical turns about its centre
    when the couple reaches mu W d, with d the distance of its corner contacts.
Tolerance after the extrapolation to rigid contacts: 2 % on rocking, 1 % on
sliding (the issue's targets). A small running-bond wall is checked against
the project's own frictional (NLP) limit analysis within 5 %.
"""
import json
import math
import os
import threading

from pathlib import Path

import pytest

import dem_validation
from dem_validation import run_scene
from dem_validation import params as P
from dem_validation.job import build_job
from dem_validation.runner import run_job
from limit.analysis import analyse
from limit.geom.interfaces import find_interfaces
from limit.model.loads import dead_and_live
from limit.model.scene import load_scene
from scenes import builders as B

from tests.conftest import check_eccentric_slab, ROOT, run_module, single_block_job

pytestmark = pytest.mark.yade
RTOL = 0.02        # rocking
RTOL_SLIDE = 0.01  # sliding


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
    assert soft < stiff  # the softer run's larger spheres put its toe further inside the block
    u = dem["displacement"]["block"]
    rz = u[2] if dim == 2 else u[4]  # 3D: rotation about y (x right, z up: toppling to +x is +ry)
    assert (rz < 0) if dim == 2 else (rz > 0)  # toppling towards +x
    assert u[0] > 0


def test_the_contact_forces_and_pose_at_the_highest_equilibrium():
    """At its highest equilibrium alpha_lo the one free block is held by the base alone, so the
    base's force on it balances its loads: F = -(f0 + alpha_lo fL) = (-alpha_lo W, 0, W) for the
    weight W = m |g| and the live load W along +x (equilibrium, to the pushover's residual)."""
    scene = B.single_block(3, 0.3, 1.0, mu=0.8)
    dem = _dem(scene)
    loaded = load_scene(scene)
    w = next(b.mass for b in loaded.blocks if b.id == "block") * math.hypot(*loaded.gravity)
    for run in dem["runs"]:
        held = run["held_forces"]
        assert held["alpha"] == pytest.approx(run["alpha_lo"])
        (a, b, *f), = held["pairs"]  # one pair of blocks in contact
        assert {a, b} == {"base", "block"}
        f = [x if b == "block" else -x for x in f]  # the force on the block
        assert f == pytest.approx([-held["alpha"] * w, 0.0, w], abs=0.01 * w)
        # its pose there, from the unloaded scene: a small elastic tilt towards the live load (+x, so
        # +ry), far from the b / h of rotation at which it would overturn, and no motion across y
        ux, uy, uz, rx, ry, rz = run["held_pose"]["block"]
        assert 0.0 < ry < 0.1 * 0.3 / 1.0 and ux > 0.0
        assert abs(uy) < 0.01 * ux and abs(rx) < 0.01 * ry


def test_single_block_slides_at_mu_3d():
    mu = 0.4
    dem = _dem(B.single_block(3, 1.0, 1.0, mu=mu))
    assert dem["alpha"] == pytest.approx(mu, rel=RTOL_SLIDE)
    for r in dem["runs"]:  # sliding does not depend on the contact stiffness
        assert r["alpha"] == pytest.approx(mu, rel=RTOL_SLIDE)
    ux, uy, uz, rx, ry, rz = dem["displacement"]["block"]
    assert ux > 0 and abs(ry) * 1.0 < 0.1 * ux and abs(uz) < 0.1 * ux


def test_a_slab_pushed_off_its_centre_slides_and_turns_on_its_corners():
    """The closed form of sliding and twisting at once (tests/conftest.py)."""
    check_eccentric_slab(_dem, RTOL_SLIDE)


def test_pair_friction_overrides_the_scene_friction():
    """A square block (b = h = 1, rocking needs alpha = 1) with mu = 0.8 everywhere except
    its joint with the base, mu = 0.3 there: it slides at alpha = 0.3."""
    dem = _dem(B.single_block(2, 1.0, 1.0, mu=0.8, friction_pairs={("base", "block"): 0.3}))
    assert dem["alpha"] == pytest.approx(0.3, rel=RTOL_SLIDE)


def test_stack_of_three_overturns_at_b_over_3h():
    n, b, h = 3, 0.3, 0.5
    dem = _dem(B.stack(n, 2, b, h, mu=0.8))
    assert dem["alpha"] == pytest.approx(b / (n * h), rel=RTOL)
    rz = [dem["displacement"][f"s{k}"][2] for k in range(n)]
    assert all(r < 0 for r in rz) and max(rz) / min(rz) > 0.8  # the stack rotates as one piece


@pytest.mark.parametrize("dim", [2, 3])
def test_portal_sways_at_b_over_h(dim):
    """Columns 0.3 x 1.5 under a lintel: the frame sways with the lintel translating,
    the columns rocking about their toes: alpha = b / h = 0.2."""
    dem = _dem(B.portal(dim=dim, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, mu=0.8))
    assert dem["alpha"] == pytest.approx(0.2, rel=RTOL)
    u, rot = dem["displacement"], 2 if dim == 2 else 4
    assert u["lintel"][0] > 0 and abs(u["lintel"][rot]) < 0.05 * abs(u["col-left"][rot])  # the lintel translates


def test_oblique_load_3d_topples_about_the_governing_edge():
    """The catalog's block-oblique-3d (0.4 x 0.25 x 1.0, load at 30 deg from x): the
    closed form in its "expected" (least b_e / ((h/2) d . n_e) over the base edges)."""
    scene = load_scene(ROOT / "scenes" / "catalog" / "block-oblique-3d.json")
    dem = _dem(scene)
    assert dem["alpha"] == pytest.approx(scene.expected["alpha"], rel=RTOL)


def twisting_block(mu=0.5, l=0.4, h=0.2, arm=0.1, f=1000.0):
    """A squat square block l x l x h on a wide base, live load a couple of two point
    forces +-f along x at y = +-arm from its centre: a moment M = 2 arm f (N m) about -z
    and no resultant force. With its weight W on four corner contacts (W/4 each) at d =
    l / sqrt(2) from the centre, it turns about its centre when M alpha = mu W d (the
    corner-to-face model's twisting strength; a uniformly pressed square has 0.383 l
    instead of 0.707 l, and the limit analysis's 10-face domain uses 2/3 l)."""
    c = [l / 2, l / 2, h / 2]
    live = [{"type": "point_force", "block": "block", "force": [f, 0.0, 0.0], "point": [c[0], c[1] + arm, c[2]]},
            {"type": "point_force", "block": "block", "force": [-f, 0.0, 0.0], "point": [c[0], c[1] - arm, c[2]]}]
    scene = B.scene("twist", 3, [B.base(3, -0.5, l + 0.5, -0.5, l + 0.5), B.box_block("block", c, [l, l, h])],
                    friction=mu, live=live)
    weight = 2000.0 * 9.81 * l * l * h
    return scene, mu * weight * (l / math.sqrt(2)) / (2 * arm * f)


def test_twisting_about_the_vertical_governs():
    scene, alpha = twisting_block()
    dem = _dem(scene)
    assert dem["alpha"] == pytest.approx(alpha, rel=RTOL_SLIDE)
    ux, uy, uz, rx, ry, rz = dem["displacement"]["block"]
    assert rz < 0 and abs(ux) + abs(uy) < 0.05 * abs(rz) * 0.2  # a turn about its centre, no slide


def test_vertex_law_takes_torques_about_the_contact_points(tmp_path):
    """With YADE's default sphericalBodies=True, Law2_ScGeom_FrictPhys_CundallStrack puts
    each contact force at the sphere radius along the normal from *both* bodies' centres:
    wrong for the polyhedron, whose centre is far from the contact (a 3-block stack then
    gave 0.183 for b/(3h) = 0.25). The model must set it off; the stack test above checks
    the physics, this one the setting itself, inside YADE."""
    script = tmp_path / "law.py"
    script.write_text(
        "import json, os, sys\n"
        f"sys.path.insert(0, {str(Path(dem_validation.__file__).parent / 'engines' / 'yade')!r})\n"
        "import yade_vertex\n"
        "job = json.load(open(sys.argv[1]))\n"
        "m = yade_vertex.VertexModel(job, job['params']['eps'][0])\n"
        "out = os.path.join(os.path.dirname(sys.argv[1]), job['result'])\n"
        "json.dump({'status': 'done', 'runs': [], 'spherical': bool(m.law.sphericalBodies)}, open(out, 'w'))\n"
        "os._exit(0)\n")
    res = run_job(single_block_job(), script=script, timeout_s=120)
    assert res["status"] == "done" and res["spherical"] is False


SURFACE_PROBE = (
    "import hashlib, json, os, sys\n"
    "sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))  # the run's copies\n"
    "import yade_vertex\n"
    "from yade import O\n"
    "job = json.load(open(sys.argv[1]))\n"
    "yade_vertex.VertexModel(job, job['params']['eps'][0])\n"
    "polys = [b.shape for b in O.bodies if b.shape.__class__.__name__ == 'Polyhedra']\n"
    "text = repr([([tuple(v) for v in s.v], list(s.GetSurfaceTriangulation())) for s in polys])\n"
    "out = os.path.join(os.path.dirname(sys.argv[1]), job['result'])\n"
    "json.dump({'status': 'done', 'runs': [], 'n': len(polys),\n"
    "           'surface': hashlib.md5(text.encode()).hexdigest()}, open(out, 'w'))\n"
    "os._exit(0)\n")


def test_two_processes_build_the_same_block_surfaces(tmp_path, monkeypatch):
    """YADE's Polyhedra take their vertex order and the triangulation of coplanar faces
    from CGAL, in an order that follows heap addresses, and so the process's history:
    a YADE started with its parent's environment built a different surface for the
    40-stone wall when that environment was 2,000 characters longer (this probe), and
    near-critical runs then drifted apart (Fig. 3-40: 0.5627 in one `make validate`,
    0.5598 in the next). The runner gives YADE the same environment, paths and fixed
    addresses from any parent: runs from different parent environments must build
    bit-identical bodies (this fails when the parent's environment is passed on)."""
    script = tmp_path / "surface.py"
    script.write_text(SURFACE_PROBE)
    scene = load_scene(ROOT / "scenes" / "catalog" / "paper-fig3-opus-poligonale-40-2d.json")
    f0, fL = dead_and_live(scene)
    job = build_job(scene, find_interfaces(scene), f0, fL, P.check({}))
    runs = []
    for pad in (0, 2000, 5000):
        monkeypatch.setenv("DEM_TEST_PADDING", "x" * pad)
        monkeypatch.setenv("PATH", "/no/such/dir" * (pad // 1000) + ":" + os.environ.get("PATH", ""))
        runs.append(run_job(job, script=script, timeout_s=300))
    assert all(r["status"] == "done" for r in runs), runs
    assert all(r["n"] == len(scene.blocks) for r in runs)
    assert len({r["surface"] for r in runs}) == 1, [r["surface"] for r in runs]


@pytest.mark.xfail(strict=True, reason="YADE's Polyhedra surfaces follow the heap, and the job file's length "
                   "moves the heap (docs/performance.md, 'One YADE process per stiffness')")
def test_the_block_surfaces_do_not_depend_on_the_job_files_length(tmp_path):
    """The same scene with an unused key of 0 or 3,000 characters in its job file must build the
    same block surfaces (the environment and addresses are fixed: the test above)."""
    script = tmp_path / "surface.py"
    script.write_text(SURFACE_PROBE)
    scene = load_scene(ROOT / "scenes" / "catalog" / "paper-fig3-opus-poligonale-40-2d.json")
    f0, fL = dead_and_live(scene)
    job = build_job(scene, find_interfaces(scene), f0, fL, P.check({}))
    runs = [run_job(dict(job, unused="x" * pad), script=script, timeout_s=300) for pad in (0, 3000)]
    assert all(r["status"] == "done" for r in runs), runs
    assert runs[0]["surface"] == runs[1]["surface"]


def test_running_bond_wall_3x3_against_the_nlp():
    """3 x 3 running-bond wall, L = H = 0.4, mu = 1.2. With friction (no dilatancy) the
    top corner - the end half block c1-3 with the top block c2-2 resting on it - rocks off
    as one piece about the outer toe of c1-3 while its joints with c1-2 and c2-1 open:
    alpha = 5/14. The associative LP forbids that opening-with-slip (it would need a
    dilatancy of mu) and finds 1.0. The DEM must follow the frictional physics: the same
    two blocks come off, far below the LP. Loaded from a settled, elastic start, its head
    joint between c1-2 and c1-3 carries friction through elastic load sharing where the
    frictional minimum has none, so the DEM collapses about 10 % above 5/14 (an
    independent vertex-model prototype: 0.389-0.394 from scratch; the report explains
    it); it must never fall below the frictional minimum."""
    scene = B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2)
    la = analyse(load_scene(scene), method="nlp").data
    a_lp, a_nlp = la["lp"]["alpha"], la["nlp"]["alpha"]
    assert la["lp"]["status"] == "optimal" and la["nlp"]["status"] == "optimal"
    assert a_nlp < 0.5 * a_lp  # a scene where friction matters
    dem = _dem(scene)
    assert 0.98 * a_nlp <= dem["alpha"] <= 1.15 * a_nlp
    assert abs(dem["alpha"] / a_lp - 1.0) > 0.5  # far from the associative answer
    # the same mechanism: the blocks that turn in the NLP turn in the DEM, toppling outwards
    nlp_rz = {k: v[2] for k, v in la["nlp"]["mechanism"].items()}
    dem_rz = {k: v[2] for k, v in dem["displacement"].items()}
    moving = lambda rz: {k for k, r in rz.items() if abs(r) > 0.1 * max(map(abs, rz.values()))}  # noqa: E731
    assert moving(dem_rz) == moving(nlp_rz) == {"c1-3", "c2-2"}
    assert dem_rz["c1-3"] < 0 and dem_rz["c2-2"] < 0


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
    assert [r["eps"] for r in dem["runs"]] == sorted(P.BY_CONTACT["vertex"]["eps"], reverse=True)
    assert dem["contact"] == "vertex" and all(r["sphere_radius"] > 0 for r in dem["runs"])
    assert dem["params"]["damping"] == P.DEFAULTS["damping"] and dem["time_s"] > 0
    hist = dem["history"]
    assert hist[0]["phase"] == "settle" and {"alpha", "outcome", "control", "eps"} <= set(hist[1])
    assert "alpha =" in proc.stdout


def test_two_runs_at_once_do_not_collide_and_repeat_exactly():
    """Two runs of one frictional wall at the same time (each competing for the cores)
    give the same alpha and the same step counts, to the last bit."""
    scene = B.running_bond_wall(2, 3, dim=2, L=0.4, H=0.2, mu=0.6)
    results = [None, None]

    def go(k):
        results[k] = run_scene(scene, timeout_s=600)

    threads = [threading.Thread(target=go, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    a, b = results
    assert a["status"] == b["status"] == "collapsed"
    assert a["alpha"] == b["alpha"] and [r["steps"] for r in a["runs"]] == [r["steps"] for r in b["runs"]]


def test_polyhedra_model_is_still_available():
    """``contact="polyhedra"`` (YADE's Polyhedra with the Python shear law) on a sliding
    block: alpha = mu at one stiffness (sliding does not depend on it)."""
    dem = run_scene(B.single_block(2, 1.0, 1.0, mu=0.3), timeout_s=300, contact="polyhedra", eps=[1e-4])
    assert dem["status"] == "collapsed" and dem["contact"] == "polyhedra"
    assert dem["alpha"] == pytest.approx(0.3, rel=RTOL_SLIDE)


# ----------------------------------------------------------------------------- DEM faults
# (the runner's own handling of a missing, crashing, hung or busy engine, with a fake one:
# tests/test_dem_runner.py)

def test_yade_crash_is_failed():
    """A job the YADE script cannot use: YADE's Python raises, YADE exits 1."""
    job = single_block_job()
    del job["blocks"][1]["vertices"]
    res = run_job(job, timeout_s=120)
    assert res["status"] == "failed" and "exited with status 1" in res["reason"] and "vertices" in res["reason"]


def test_yade_stopped_by_its_time_limit_is_failed():
    """The real YADE stopped by a time limit shorter than the run."""
    dem = run_scene(B.running_bond_wall(6, 5, dim=2, mu=0.65), timeout_s=4)  # a stack now ends in < 4 s
    assert dem["status"] == "failed" and "timed out" in dem["reason"] and dem.get("alpha") is None
    assert 0 < dem["cpu_s"] <= dem["time_s"] + 1.0  # the CPU it had used when it was killed


def test_nan_in_the_simulation_is_failed():
    job = single_block_job()
    job["f0"][0][0] = float("nan")  # a NaN force drives the block's position to NaN
    res = run_job(job, timeout_s=120)
    assert res["status"] == "failed" and "NaN" in res["reason"]

