"""``limit solve`` (limit/cli.py): the result file, its exit statuses and its option checks
(docs/formats.md, 'Result file' and 'Commands')."""
import json
import math

import pytest

from limit.solve import lp as lpmod, nlp
from limit.cli import main

from tests.conftest import ROOT

SIDE = ROOT / "scenes" / "catalog" / "side-by-side-2d.json"
# side-by-side-2d (mu 0.5): frictional 23/61, associative 7/17; closed forms in the docstring of
# scenes/builders.side_by_side (outside limit/). 23/61 = (0.6*0.3*0.5 + 0.2*0.2*1.25/2) / (0.2*1.25/2 + 0.6*0.3).
ALPHA_NLP, ALPHA_LP = 23 / 61, 7 / 17


def _run_solve(capsys, *args):
    """``limit`` with ``args`` in this process: (returncode, stdout, stderr) as of a subprocess."""
    import types

    code = main(list(args))
    out = capsys.readouterr()
    return types.SimpleNamespace(returncode=code, stdout=out.out, stderr=out.err)


def _strict_load(path):
    """Parse a JSON file, rejecting NaN / Infinity tokens (not JSON, though Python's json writes them)."""
    def no_constant(tok):
        raise ValueError(f"non-JSON constant {tok}")
    return json.loads(path.read_text(), parse_constant=no_constant)


def test_solve_json_keys_and_values(tmp_path, capsys):
    """Exit 0; the contract keys of the result file, nothing private ('_' keys); side-by-side-2d has
    3 blocks (base, A, B), 2 free, 3 interfaces (base|A, base|B, A|B); LP 7/17, NLP 23/61; the LP
    mechanism has [ux, uy, rz] per free block."""
    out = tmp_path / "r.json"
    p = _run_solve(capsys, "solve", str(SIDE), "--json", str(out))
    assert p.returncode == 0, p.stderr
    r = _strict_load(out)
    assert set(r) == {"scene", "dim", "n_blocks", "n_free_blocks", "n_interfaces", "lp", "nlp", "units"}
    assert r["units"]["length"] == "m"
    assert (r["scene"], r["dim"], r["n_blocks"], r["n_free_blocks"], r["n_interfaces"]) == \
        ("side-by-side-2d", 2, 3, 2, 3)
    assert {"status", "alpha", "time_s", "solver", "timings", "attempts", "model", "verification",
            "mechanism", "normalisation", "interfaces", "counts"} <= set(r["lp"])
    assert {"status", "alpha", "time_s", "verification", "runs"} <= set(r["nlp"])
    assert not any(k.startswith("_") for part in (r, r["lp"], r["nlp"]) for k in part)
    assert r["lp"]["status"] == "optimal" and r["lp"]["alpha"] == pytest.approx(ALPHA_LP, rel=1e-6)
    assert r["nlp"]["status"] == "optimal" and r["nlp"]["alpha"] == pytest.approx(ALPHA_NLP, rel=1e-6)
    assert set(r["lp"]["mechanism"]) == {"A", "B"}
    assert all(len(v) == 3 for v in r["lp"]["mechanism"].values())
    assert sorted(map(sorted, r["lp"]["interfaces"]["pairs"])) == [["A", "B"], ["A", "base"], ["B", "base"]]
    # the printed summary carries both numbers
    assert f"{ALPHA_LP:.6g}" in p.stdout and f"{ALPHA_NLP:.6g}" in p.stdout


def test_solve_json_nan_becomes_null(tmp_path, monkeypatch):
    """A solver that reports no solve time gives timings NaN (limit/solve/lp.py, _solve): the file holds
    null there and stays strict JSON; the other numbers are unchanged."""
    real = lpmod._solve

    def no_solve_time(*a, **k):
        status, t = real(*a, **k)
        return status, dict(t, solve_s=float("nan"), compile_s=float("nan"))

    monkeypatch.setattr(lpmod, "_solve", no_solve_time)
    out = tmp_path / "r.json"
    assert main(["solve", str(SIDE), "--method", "lp", "--solver", "clarabel", "--json", str(out)]) == 0
    r = _strict_load(out)
    assert "NaN" not in out.read_text()
    assert "solve_s" in r["lp"]["timings"] and r["lp"]["timings"]["solve_s"] is None
    assert r["lp"]["timings"]["compile_s"] is None
    assert r["lp"]["alpha"] == pytest.approx(ALPHA_LP, rel=1e-6)
    assert math.isfinite(r["lp"]["timings"]["solver_total_s"])


def test_solve_exit_1_when_nlp_fails_keeps_lp_bound(tmp_path, monkeypatch, capsys):
    """Step 2 forced to fail (every NLP end point rejected by its check): exit 1, the result file is
    still written with the checked LP bound 7/17 and the NLP 'failed' with alpha null and a reason."""
    monkeypatch.setattr(nlp, "check", lambda N, z, a: (False, {"complementarity": 1.0}, "forced failure"))
    out = tmp_path / "r.json"
    assert main(["solve", str(SIDE), "--json", str(out)]) == 1
    r = _strict_load(out)
    assert r["lp"]["status"] == "optimal" and r["lp"]["alpha"] == pytest.approx(ALPHA_LP, rel=1e-6)
    assert r["nlp"]["status"] == "failed" and r["nlp"]["alpha"] is None and r["nlp"]["reason"]
    printed = capsys.readouterr().out
    assert f"{ALPHA_LP:.6g}" in printed and "failed" in printed


@pytest.mark.parametrize("args, option", [
    (["--slide-faces", "3"], "--slide-faces"),
    (["--slide-faces", "5"], "--slide-faces"),
    (["--slide-faces", "362"], "--slide-faces"),
    (["--nlp-time-budget", "0"], "--nlp-time-budget"),
    (["--nlp-time-budget", "-1"], "--nlp-time-budget"),
    (["--nlp-time-budget", "nan"], "--nlp-time-budget"),
    (["--global", "--global-time-limit", "0"], "--global-time-limit"),
    (["--global", "--global-time-limit", "nan"], "--global-time-limit"),
])
def test_solve_rejects_bad_option_values_in_one_line(args, option, capsys, tmp_path):
    """Values argparse lets through but cmd_solve rejects: exit 2, one line on stderr naming the
    option, no result file."""
    out = tmp_path / "r.json"
    assert main(["solve", str(SIDE), "--json", str(out), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and option in err[0], err
    assert not out.exists()


@pytest.mark.parametrize("args, option", [
    (["--method", "exact"], "--method"),
    (["--solver", "gurobi"], "--solver"),
    (["--model", "fem"], "--model"),
    (["--slide-fit", "tight"], "--slide-fit"),
    (["--nlp-solver", "ipopt"], "--nlp-solver"),
    (["--slide-faces", "four"], "--slide-faces"),
    (["--nlp-time-budget", "soon"], "--nlp-time-budget"),
    (["--global-time-limit", "soon"], "--global-time-limit"),
])
def test_solve_rejects_bad_choices(args, option, capsys):
    """Values argparse itself rejects: exit 2 and a message naming the option."""
    with pytest.raises(SystemExit) as exc:
        main(["solve", str(SIDE), *args])
    assert exc.value.code == 2
    assert option in capsys.readouterr().err


@pytest.mark.parametrize("extra,cone", [((), "4-face circumscribed"), (("--slide-faces", "24"), "24-face inscribed")])
def test_the_lp_line_names_the_3d_friction_cone(extra, cone, capsys):
    """The summary's LP line says which friction cone a 3D LP used (the paper model's default 4
    circumscribed faces, or what --slide-faces asks for); a 2D LP line names none."""
    assert main(["solve", str(ROOT / "scenes" / "catalog" / "block-rocking-3d.json"), "--method", "lp", *extra]) == 0
    assert f"paper interfaces, {cone} friction cone)" in capsys.readouterr().out
    assert main(["solve", str(SIDE), "--method", "lp"]) == 0
    out = capsys.readouterr().out
    assert "paper interfaces)" in out and "friction cone" not in out


def test_solve_keeps_its_result_in_the_cache(tmp_path, write_scene, monkeypatch, capsys):
    """A second `limit solve` of the same scene with the same options comes from the cache (same
    lines printed, the same result file); another option, a changed scene or --no-cache solve again."""
    import json as _json

    from limit.cli import main
    from scenes import builders as B

    monkeypatch.delenv("LIMIT_NO_CACHE", raising=False)
    scene = write_scene(B.portal(dim=2, name="cached-portal"))
    args = ["solve", str(scene), "--cache", str(tmp_path / "c")]
    assert main(args + ["--json", str(tmp_path / "a.json")]) == 0
    first = capsys.readouterr()
    assert "result cache" not in first.err
    assert main(args + ["--json", str(tmp_path / "b.json")]) == 0
    second = capsys.readouterr()
    assert "from the result cache" in second.err and second.out == first.out
    a, b = (_json.loads((tmp_path / f).read_text()) for f in ("a.json", "b.json"))
    assert a == b
    assert main(args + ["--method", "lp"]) == 0 and "result cache" not in capsys.readouterr().err
    assert main(args + ["--no-cache"]) == 0 and "result cache" not in capsys.readouterr().err
    d = B.portal(dim=2, name="cached-portal")
    d["friction"] = 0.9
    scene.write_text(_json.dumps(d))
    assert main(args) == 0 and "result cache" not in capsys.readouterr().err


def test_progress_of_a_solve_goes_to_stderr_when_asked(capsys, monkeypatch):
    """LIMIT_LOG_LEVEL=INFO: the LP's line and one line per step-2 run on stderr, the summary on
    stdout unchanged; without it (stderr not a terminal) no progress lines; a level that logging
    does not know is rejected with the variable's name (exit 2)."""
    monkeypatch.setenv("LIMIT_LOG_LEVEL", "INFO")
    p = _run_solve(capsys, "solve", str(SIDE), "--method", "nlp", "--no-cache")
    assert p.returncode == 0
    assert f"side-by-side-2d: LP optimal, alpha {ALPHA_LP:.6g}" in p.stderr
    runs = [ln for ln in p.stderr.splitlines() if ln.startswith("step 2: run ")]
    assert runs and runs[0].startswith("step 2: run 1 of ")
    assert f"side-by-side-2d: step 2 optimal, alpha {ALPHA_NLP:.6g}" in p.stderr
    assert "step 2: run" not in p.stdout
    monkeypatch.delenv("LIMIT_LOG_LEVEL")
    q = _run_solve(capsys, "solve", str(SIDE), "--method", "nlp", "--no-cache")
    assert q.returncode == 0 and "step 2: run" not in q.stderr
    monkeypatch.setenv("LIMIT_LOG_LEVEL", "chatty")
    r = _run_solve(capsys, "solve", str(SIDE), "--no-cache")
    assert r.returncode == 2 and "LIMIT_LOG_LEVEL" in r.stderr
