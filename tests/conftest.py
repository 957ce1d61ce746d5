import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# `limit solve` keeps its results in the repository's cache; the suite solves afresh (its subprocesses
# inherit this), and tests/test_cli.py checks the cache with a folder of its own
os.environ["LIMIT_NO_CACHE"] = "1"


@pytest.fixture
def write_scene(tmp_path):
    """Write a scene dict (or raw text) to a file and return its path."""
    counter = {"n": 0}

    def _write(content, name=None):
        counter["n"] += 1
        p = tmp_path / (name or f"scene{counter['n']}.json")
        p.write_text(content if isinstance(content, str) else json.dumps(content))
        return p

    return _write


def run_module(module, *args, timeout=600):
    """Run ``python -m module args`` in a subprocess; returns CompletedProcess (text)."""
    return subprocess.run([sys.executable, "-m", module, *map(str, args)], capture_output=True, text=True,
                          cwd=ROOT, timeout=timeout)


def single_block_job(**knobs) -> dict:
    """The DEM job (dem_validation.job) of one 0.3 x 1.0 m block on a base, mu = 0.8, with the
    given YADE knobs: what the runner tests hand to a real or a fake engine."""
    from dem_validation import params
    from dem_validation.job import build_job
    from limit.geom.interfaces import find_interfaces
    from limit.model.loads import dead_and_live
    from limit.model.scene import load_scene
    from scenes import builders

    scene = load_scene(builders.single_block(2, 0.3, 1.0, mu=0.8))
    f0, fL = dead_and_live(scene)
    return build_job(scene, find_interfaces(scene), f0, fL, params.check(knobs))


#: the catalog scenes that the whole-catalog tests check in the fast subset too (a rocking block,
#: a frictional pair, a 2D arch, a 3D portal); the other scenes' cases carry the slow marker
FAST_CATALOG = ("block-rocking-2d", "side-by-side-2d", "arch-semicircular-9-2d", "portal-3d")


def catalog_params(paths) -> list:
    """pytest parameters of catalog files, named by their scene, marked slow outside FAST_CATALOG."""
    return [pytest.param(p, id=p.stem, marks=() if p.stem in FAST_CATALOG else pytest.mark.slow) for p in paths]


def check_eccentric_slab(run, rtol: float, e: float = 0.25, mu: float = 0.6) -> None:
    """An engine on scenes.builders.eccentric_slab: ``run(scene)`` gives its collapsed DEM result.
    Sliding and twisting at once on the corner contacts: the closed form of
    scenes.builders.eccentric_slab_alpha (0.54417 at e = 0.25 m, mu 0.6; derivation there), where
    the paper's joint, with sliding and twisting independent, would slide at mu. The slab turns
    clockwise (-rz) while it moves along +x."""
    from scenes import builders as B

    dem = run(B.eccentric_slab(e=e, mu=mu))
    assert dem["alpha"] == pytest.approx(B.eccentric_slab_alpha(e, mu=mu), rel=rtol)
    ux, uy, uz, rx, ry, rz = dem["displacement"]["slab"]
    assert ux > 0 and rz < 0


def eccentric_slab_run(scene, alpha: float, rz: float = -1e-3) -> dict:
    """A collapsed DEM result of the loaded eccentric slab (scenes.builders.eccentric_slab) at
    ``alpha``: a motion along +x turning by ``rz`` (rad), and at its highest equilibrium the
    base's force (-alpha W, 0, W) on the slab, W its weight (N)."""
    import numpy as np

    w = next(b for b in scene.blocks if b.id == "slab").mass * float(np.linalg.norm(scene.gravity))
    return {"status": "collapsed", "alpha": alpha, "displacement": {"slab": [1e-3, 0, 0, 0, 0, rz]},
            "runs": [{"eps": 2.5e-6, "held_forces": {"alpha": alpha, "pairs": [["base", "slab", -alpha * w, 0.0, w]]}}]}


def side_by_side_collapse_forces(scene, mu: float = 0.5) -> tuple[dict, tuple]:
    """The contact forces of the closed-form frictional collapse of the 2D side-by-side blocks
    (scenes.builders.side_by_side, a loaded scene), per block pair as a DEM run records them
    (``held_forces``: the force on the second block from the first, N), and the three normal
    forces (N) under A, under B and between them. A rotates about its toe (b1, 0) and touches B
    only at B's top corner (b1, h2), with a horizontal thrust T and the friction mu T lifting B;
    B slides on the base. Moments of A about its toe: alpha W_A h1/2 = W_A b1/2 + T h2 (the
    friction acts at the toe's x); B along x: T + alpha W_B = mu N_B with N_B = W_B - mu T, so
    T = W_B (mu - alpha) / (1 + mu^2), and the base carries N_A = W_A + mu T under A."""
    import math

    from scenes import builders

    alpha = builders.side_by_side_alpha(mu=mu)
    g = math.hypot(*scene.gravity)
    wa, wb = (next(b.mass for b in scene.blocks if b.id == k) * g for k in "AB")
    t = wb * (mu - alpha) / (1 + mu * mu)
    nb = wb - mu * t
    pairs = [["base", "A", -alpha * wa + t, wa + mu * t, 0.0], ["base", "B", -mu * nb, nb, 0.0],
             ["A", "B", t, mu * t, 0.0]]
    return {"alpha": alpha, "pairs": pairs}, (wa + mu * t, nb, t)
