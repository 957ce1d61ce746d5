"""The public API (``import limit``) and the installed command."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

import limit
from scenes import builders as B


@pytest.mark.slow  # about 4 s: a fresh interpreter that imports limit and solves
def test_the_readme_one_liner():
    p = subprocess.run([sys.executable, "-c", "import limit; r = limit.analyse(limit.load_scene("
                        "'scenes/catalog/block-rocking-2d.json')); print(r.lp.alpha)"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert float(p.stdout) == pytest.approx(0.3, rel=1e-8)  # b / h


def test_typed_result_of_a_frictional_scene():
    """side-by-side, mu 0.5: associative 7/17, frictional 23/61 (scenes/builders.side_by_side)."""
    r = limit.analyse(B.side_by_side(dim=2, mu=0.5))
    assert isinstance(r, limit.Result) and isinstance(r.lp, limit.StepResult)
    assert r.lp.alpha == pytest.approx(7 / 17, rel=1e-6) and r.nlp.status == "optimal"
    assert r.alpha == r.nlp.alpha == pytest.approx(23 / 61, rel=1e-6)
    d = r.to_dict()
    assert json.loads(json.dumps(d))["nlp"]["alpha"] == r.nlp.alpha  # JSON-ready, no in-memory objects
    assert not any(k.startswith("_") for k in d)


def test_typed_verdict_of_a_scene_with_a_demand():
    """The catalog's portal states ag = 0.2 g, S = 1.2, q = 2: the linear check's demand is
    ag S / q = 0.2 x 9.81 x 1.2 / 2 = 1.1772 m/s^2 (by hand). The typed verdict carries the
    file's numbers; ``passed`` is every check made passing. A scene without a demand has none."""
    r = limit.analyse("scenes/catalog/portal-2d.json")
    v, d = r.verdict, r.to_dict()["verdict"]
    assert isinstance(v, limit.Verdict) and v.status == "done" and v.step in ("lp", "nlp")
    assert v.linear.demand == pytest.approx(1.1772, rel=1e-12)
    assert v.linear.ratio == pytest.approx(v.linear.capacity / v.linear.demand, rel=1e-12)
    assert v.a0_star == d["linear"]["a0_star"] == v.linear.capacity and v.alpha0 == pytest.approx(r.alpha)
    assert v.passed == (d["check"]["linear"]["pass"] and d["check"]["nonlinear"]["pass"])
    assert limit.analyse(B.single_block(2, 0.3, 1.0)).verdict is None


def test_the_answer_is_none_when_step_2_failed(monkeypatch):
    from limit.solve import nlp
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    r = limit.analyse(B.side_by_side(dim=2, mu=0.5))
    assert r.nlp.status == "failed" and r.alpha is None and r.lp.alpha == pytest.approx(7 / 17, rel=1e-6)
    with pytest.raises(limit.SolverError, match=r"step 2 failed: .*forced failure"):
        r.raise_for_status()


def test_raise_for_status_passes_an_answer_through():
    """An answer, and an infeasible LP (the dead load alone collapses: an answer too), raise nothing."""
    r = limit.analyse(B.single_block(2, 0.3, 1.0))
    assert r.raise_for_status() is r and r.alpha == pytest.approx(0.3, rel=1e-6)
    d = B.single_block(2, 0.3, 1.0)
    d["gravity"] = [5.0, -9.81]  # tilted by atan(5 / 9.81) = 27 deg > atan(b / h) = 16.7 deg: it overturns
    r = limit.analyse(d).raise_for_status()
    assert r.lp.status == "infeasible" and r.alpha is None


def test_errors_are_exported():
    with pytest.raises(limit.SceneError, match="format"):
        limit.load_scene({"format": "x"})
    assert issubclass(limit.SceneWarning, UserWarning)


@pytest.mark.slow  # about 4 s: the installed command in two subprocesses
def test_the_installed_command_and_its_version():
    exe = Path(sys.executable).with_name("limit")
    p = subprocess.run([str(exe), "--version"], capture_output=True, text=True)
    assert p.returncode == 0 and p.stdout.strip() == f"limit {limit.__version__}"
    p = subprocess.run([str(exe), "info", "scenes/catalog/portal-2d.json"], capture_output=True, text=True)
    assert p.returncode == 0 and "portal-2d" in p.stdout


def test_importing_limit_sets_no_environment_variable():
    p = subprocess.run([sys.executable, "-c", "import os; before = dict(os.environ); import limit; "
                        "print(sorted(set(os.environ.items()) ^ set(before.items())))"],
                       capture_output=True, text=True, env={"PATH": "/usr/bin:/bin"})
    assert p.returncode == 0 and p.stdout.strip() == "[]", p.stderr


def test_the_readme_example_scene():
    """examples/minimal-2d.json: a 0.4 x 1 m stone overturns at b / h = 0.4 (mu 0.6 > 0.4)."""
    r = limit.analyse(limit.load_scene("examples/minimal-2d.json"))
    assert r.lp.alpha == pytest.approx(0.4, rel=1e-8) and r.alpha == pytest.approx(0.4, rel=1e-8)
    assert r.nlp.status == "skipped" and set(r.lp.mechanism) == {"stone"}
