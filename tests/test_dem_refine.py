"""The vertex model's rule for one more, stiffer, YADE run (dem_validation/engines/yade/refine.py),
checked without YADE: the host runs it between the YADE processes."""
import pytest

from dem_validation import params
from dem_validation.engines.yade import refine

P = params.check({})


def _run(eps, alpha, cpu, status="collapsed", dead=False):
    return {"eps": eps, "alpha": alpha, "cpu_s": cpu, "status": status, "dead_load_collapse": dead}


def test_runs_that_agree_within_refine_rtol_need_no_stiffer_run():
    """0.50 and 0.51 are 2 % apart, under the default refine_rtol of 5 %: no run follows, and
    nothing is said."""
    assert refine.next_eps([_run(1e-5, 0.50, 10), _run(2.5e-6, 0.51, 20)], 0, 30.0, P) == (None, "")


def test_runs_apart_get_a_quarter_of_the_stiffest_eps_when_it_fits():
    """0.45 and 0.50 are 10 % apart; 30 s spent + 2 x 20 s projected = 70 s <= 1500 s."""
    eps, why = refine.next_eps([_run(1e-5, 0.45, 10), _run(2.5e-6, 0.50, 20)], 0, 30.0, P)
    assert eps == pytest.approx(6.25e-7) and why == ""


def test_a_run_that_collapsed_under_the_dead_load_is_apart_from_one_that_collapsed_under_load():
    soft = _run(1e-5, None, 5, dead=True)
    assert refine.apart(soft, _run(2.5e-6, 0.3, 5), 0.05) and not refine.apart(soft, dict(soft), 0.05)


def test_a_stiffer_run_that_would_not_fit_the_cpu_cap_is_not_made_and_the_result_says_why():
    """400 s spent + 2 x 600 s projected = 1600 s > refine_cpu_s 1500 s: no run, and the reason
    names the knob and the projection; with the cap at 1600 s it fits exactly."""
    runs = [_run(1e-5, 0.45, 150), _run(2.5e-6, 0.50, 600)]
    eps, why = refine.next_eps(runs, 0, 400.0, P)
    assert eps is None and "refine_cpu_s = 1500" in why and "about 1600 s" in why
    assert refine.next_eps(runs, 0, 400.0, dict(P, refine_cpu_s=1600.0))[0] == pytest.approx(6.25e-7)


def test_refine_max_bounds_the_extra_runs_and_is_named():
    runs = [_run(1e-5, 0.45, 1), _run(2.5e-6, 0.50, 1)]
    eps, why = refine.next_eps(runs, 2, 2.0, P)
    assert eps is None and "refine_max = 2" in why


def test_the_cpu_cap_is_a_checked_knob():
    with pytest.raises(ValueError, match="refine_cpu_s"):
        params.check({"refine_cpu_s": 0})


def _fake_yade(alphas, calls):
    """A stand-in for one YADE process (``run_job``): records the job, returns one run at the
    job's single stiffness, collapsing at ``alphas[eps]`` with a 1 % bracket."""
    def run_job(job, **kw):
        calls.append(job)
        eps = job["stiffness"]["eps"]
        a = alphas[eps]
        return {"status": "done", "length": 1.0, "cpu_s": 10.0, "steps_total": 100,
                "runs": [{"eps": eps, "status": "collapsed", "alpha": a, "alpha_lo": 0.99 * a, "alpha_hi": 1.01 * a,
                          "steps": 100, "cpu_s": 9.0}]}
    return run_job


def test_each_stiffness_runs_in_a_process_of_its_own(monkeypatch):
    """The vertex model's stiffnesses run one per YADE process (a second model built in one
    process does not repeat between processes): each job carries one ``stiffness``, a stiffer run
    starts from the softer one's bracket, a run that is not the stiffest planned when it starts
    has the wider tolerance, and
    a stiffer run follows while the two stiffest are more than ``refine_rtol`` apart."""
    from dem_validation.engines import yade

    calls: list = []
    alphas = {1e-5: 0.40, 2.5e-6: 0.50, 6.25e-7: 0.51}  # 0.40 -> 0.50 is 20 % apart: one more run
    monkeypatch.setattr(yade, "run_job", _fake_yade(alphas, calls))
    out = yade.per_stiffness({"params": P}, P)
    assert out["status"] == "done"
    assert [c["stiffness"]["eps"] for c in calls] == [1e-5, 2.5e-6, 6.25e-7]
    assert calls[0]["stiffness"]["hint"] is None
    assert calls[1]["stiffness"]["hint"] == pytest.approx([0.396, 0.404])
    assert calls[2]["stiffness"]["hint"] == pytest.approx([0.495, 0.505])
    soft = max(P["alpha_rtol"], P["alpha_rtol_soft"])
    assert [c["stiffness"]["alpha_rtol"] for c in calls] == [soft, P["alpha_rtol"], P["alpha_rtol"]]
    assert [r["alpha"] for r in out["runs"]] == [0.40, 0.50, 0.51]
    assert out["cpu_s"] == 30.0 and out["steps_total"] == 300 and "refinement" not in out


def test_a_failed_stiffness_ends_the_runs_and_names_its_eps(monkeypatch):
    from dem_validation.engines import yade

    calls: list = []
    good = _fake_yade({1e-5: 0.4}, calls)

    def run_job(job, **kw):
        if job["stiffness"]["eps"] == 1e-5:
            return good(job, **kw)
        calls.append(job)
        return {"status": "failed", "reason": "timed out", "cpu_s": 5.0}
    monkeypatch.setattr(yade, "run_job", run_job)
    out = yade.per_stiffness({"params": P}, P, timeout_s=100.0)
    assert out["status"] == "failed" and out["reason"] == "the run at eps 2.5e-06: timed out"
    assert len(out["runs"]) == 1 and out["cpu_s"] == 15.0


def test_a_failed_later_stiffness_keeps_the_earlier_runs_in_the_result():
    """The result of a failed sequence still carries the run that ended (nothing lost on failure)."""
    from dem_validation.engines.yade.assemble import assemble

    raw = {"status": "failed", "reason": "the run at eps 2.5e-06: timed out", "cpu_s": 15.0,
           "runs": [{"eps": 1e-5, "status": "collapsed", "alpha": 0.4}]}
    res = assemble(raw, P)
    assert res.status == "failed" and res.runs[0]["alpha"] == 0.4
