"""The vertex model's rule for one more, stiffer, YADE run (dem_validation/engines/yade/refine.py),
checked on the host without YADE: the same module runs inside the YADE process."""
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
