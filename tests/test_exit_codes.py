"""Every command line maps the same exceptions to the same exit statuses (docs/formats.md,
'Commands'): the one mapping is limit.errors.run_command."""
import pytest

import dem_validation.cli
import limit.cli
import reports.vtk
from limit.errors import SceneError, SolverError

CASES = [
    (SceneError("blocks[0]: bad"), 2, "error: blocks[0]: bad"),
    (BrokenPipeError(), 0, ""),
    (KeyboardInterrupt(), 130, "interrupted"),
    (SolverError("no answer"), 1, "failed: SolverError: no answer"),
    (RuntimeError("boom"), 1, "failed: RuntimeError: boom"),
]


def _raiser(exc):
    def command(*args, **kwargs):
        raise exc
    return command


def _limit(monkeypatch, exc):
    monkeypatch.setitem(limit.cli.COMMANDS, "info", _raiser(exc))
    return limit.cli.main(["info", "scene.json"])


def _dem(monkeypatch, exc):
    monkeypatch.setattr(dem_validation.cli, "cmd_run", _raiser(exc))
    return dem_validation.cli.main(["run", "scene.json"])


def _vtk(monkeypatch, exc):
    monkeypatch.setattr(reports.vtk, "_run", _raiser(exc))
    return reports.vtk.main(["scene.json", "-o", "out.vtk"])


CLIS = {"limit": (_limit, "LIMIT_DEBUG"), "dem_validation": (_dem, "DEM_DEBUG"), "reports.vtk": (_vtk, "LIMIT_DEBUG")}


@pytest.mark.parametrize("cli", CLIS)
@pytest.mark.parametrize("exc,status,message", CASES, ids=lambda c: type(c).__name__ if isinstance(c, BaseException) else None)
def test_same_exit_status(cli, exc, status, message, monkeypatch, capsys):
    run, debug_env = CLIS[cli]
    monkeypatch.delenv(debug_env, raising=False)
    assert run(monkeypatch, exc) == status
    err = capsys.readouterr().err
    assert err.startswith(message) if message else err == ""


@pytest.mark.parametrize("cli", CLIS)
def test_debug_env_reraises(cli, monkeypatch):
    run, debug_env = CLIS[cli]
    monkeypatch.setenv(debug_env, "1")
    with pytest.raises(RuntimeError, match="boom"):
        run(monkeypatch, RuntimeError("boom"))
