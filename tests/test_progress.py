"""The status line of long runs (reports/progress.py): the running stages with the engines' own
progress records, and the time left from the stages' costs."""
import time

import pytest

from reports import progress as prog


def test_time_left_comes_from_the_costs_not_the_rate(tmp_path):
    """Two slots, 600 s queued, two stages of 100 s and 300 s just started: (600 + 100 + 300) / 2
    = 500 s left, whatever the rate so far (no stage has finished)."""
    board = prog.Board(tmp_path, slots=2, show=lambda _: None, queued_cost=1000.0)
    try:
        board.start("dem", "wall", 100.0)
        board.start("lmgc", "wall", 300.0)
        assert board.queued == pytest.approx(600.0)
        assert board.eta() == pytest.approx(500.0, abs=1.0)
    finally:
        board.close()


def test_a_stage_past_its_estimate_keeps_a_tenth_of_it():
    board = prog.Board(None, slots=1, show=lambda _: None)
    try:
        board.start("dem", "slow", 1.0)
        board.running[("dem", "slow")] = (time.monotonic() - 50.0, 10.0)  # started 50 s ago, cost 10 s
        assert board.eta() == pytest.approx(1.0)
    finally:
        board.close()


def test_the_line_shows_each_engines_latest_record(tmp_path):
    board = prog.Board(tmp_path, slots=2, show=lambda _: None)
    try:
        board.start("dem", "fig6", 300.0)
        board.start("lmgc", "arch", 60.0)
        yade = prog.StageProgress(prog.path_for(tmp_path, "dem", "fig6"))
        yade({"eps": 1e-5, "alpha": 0.34681, "step": 123456, "residual": 1e-3})
        yade({"eps": 1e-5, "alpha": 0.35, "step": 123457, "residual": 1e-3})  # within REFRESH_S: not written
        prog.StageProgress(prog.path_for(tmp_path, "lmgc", "arch"))(
            {"phase": "bisect", "alpha": 0.1333, "outcome": "collapsed", "step": 900})
        line = board.line()
    finally:
        board.close()
    assert "fig6 dem" in line and "(eps 1e-05 alpha 0.3468 step 123k)" in line
    assert "arch lmgc" in line and "(bisect alpha 0.1333 collapsed step 900)" in line
    assert line.endswith("left") and "about" in line


def test_the_line_is_shown_while_stages_run(tmp_path, monkeypatch):
    """A stage handed to the cluster is 'waiting' until its worker begins it (its progress file).
    The board refreshes every 0.4 s here instead of every REFRESH_S."""
    monkeypatch.setattr(prog, "REFRESH_S", 0.4)
    shown = []
    board = prog.Board(tmp_path, slots=1, show=shown.append)
    board.start("la", "dome", 5.0)
    assert "1 stage(s) waiting for a worker" in board.line() and "dome la" not in board.line()
    prog.StageProgress(prog.path_for(tmp_path, "la", "dome"))  # the worker begins it
    time.sleep(2.5 * prog.REFRESH_S)
    board.close()
    assert shown and all("running: dome la" in s for s in shown)


def test_the_pace_of_finished_stages_scales_the_time_left():
    """A stage of cost 100 s that took 200 s: this machine runs at half the measured speed, so
    300 s of queued cost on one slot leave about 600 s."""
    board = prog.Board(None, slots=1, show=lambda _: None, queued_cost=400.0)
    try:
        board.start("dem", "a", 100.0)
        board.running[("dem", "a")] = (time.monotonic() - 200.0, 100.0)
        board.finish("dem", "a")
        assert board.pace() == pytest.approx(2.0, rel=1e-3)
        assert board.eta() == pytest.approx(600.0, rel=1e-3)
    finally:
        board.close()


def test_stages_past_their_cost_set_the_pace_before_any_finishes():
    """Nothing has finished, and the two stages running (costs 100 s and 200 s) began 250 s and
    500 s ago on their workers: this machine takes at least (250 + 500) / (100 + 200) = 2.5 s per
    second of cost. 400 s of queued cost on two slots then leave 2.5 x 400 / 2 = 500 s plus a
    tenth of each running stage's scaled cost, (25 + 50) / 2: 537.5 s, where the costs alone
    would say 200 s plus (10 + 20) / 2."""
    board = prog.Board(None, slots=2, show=lambda _: None, queued_cost=700.0)
    try:
        board.start("dem", "a", 100.0)
        board.start("dem", "b", 200.0)
        now = time.monotonic()
        board.running[("dem", "a")] = (now - 250.0, 100.0)
        board.running[("dem", "b")] = (now - 500.0, 200.0)
        begun = {("dem", "a"): 250.0, ("dem", "b"): 500.0}
        assert board.pace() == 1.0 and board.pace(begun) == pytest.approx(2.5)
        assert board.eta(begun) == pytest.approx(537.5, rel=1e-3)
    finally:
        board.close()
