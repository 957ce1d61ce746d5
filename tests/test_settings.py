"""The settings (limit/settings.py): one frozen dataclass of route thresholds, time budgets and
check tolerances, overridden through limit.Options and ``limit solve --set``, read by the code
from the problem it solves, part of the result cache's key, listed in docs/settings.md; and one
TOL_COMP in the library.

The expected routes and solvers are those the settings name (a threshold of 1 free block sends
every scene to the large route; a threshold of 0 unknowns leaves SLSQP no problem), not values
the code computes."""
import dataclasses
import json
import re
from pathlib import Path

import pytest

import limit
from limit import cli, settings
from limit.model.assemble import assemble
from limit.model.scene import load_scene
from limit.settings import DEFAULT, Settings
from limit.solve import lp as lpmod
from scenes import builders as B

ROOT = Path(__file__).resolve().parents[1]
ROCKING = str(ROOT / "scenes" / "catalog" / "block-rocking-2d.json")


def _wall():
    """A 3 x 3 running-bond wall (10 free blocks) whose step 2 takes the successive LP by default."""
    return B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.3, mu=0.6)


def _solvers(r) -> set:
    return {run["solver"] for run in r.nlp.data["runs"]}


# -- the dataclass -----------------------------------------------------------------------------


def test_every_setting_has_a_group_unit_and_meaning():
    fields = dataclasses.fields(Settings)
    assert len(fields) >= 15
    for f in fields:
        assert f.metadata["group"] in settings.GROUPS, f.name
        assert f.metadata["unit"] and len(f.metadata["doc"]) > 20, f.name
        assert f.type in (int, float, bool, tuple), f.name
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT.large_min_free = 1


def test_the_defaults_are_the_values_the_modules_had():
    """The values the thresholds and tolerances had as module constants (step2, step2_large, nlp,
    solvers, verify), so that a run at the defaults gives the results it gave."""
    assert (DEFAULT.large_min_free, DEFAULT.global_max_blocks, DEFAULT.very_large_min_free) == (200, 30, 5000)
    assert (DEFAULT.one_round_min_free, DEFAULT.prox_min_free, DEFAULT.slsqp_max_vars) == (2000, 5000, 250)
    assert (DEFAULT.lp_ipm_min_dof, DEFAULT.highs_max_vars, DEFAULT.many_restarts_max_vars) == (3000, 3000, 5000)
    assert (DEFAULT.nlp_time_budget, DEFAULT.hard_factor, DEFAULT.global_time_limit) == (120.0, 5.0, 120.0)
    assert DEFAULT.also_iterative is True and DEFAULT.lower_by == 1e-9
    assert [DEFAULT.tol_eq, DEFAULT.tol_yield, DEFAULT.tol_kin, DEFAULT.tol_gap, DEFAULT.tol_comp] == [1e-6] * 5
    assert DEFAULT.sla_comp_target == 1e-7
    # step2_large's module constants OMEGA, OMEGA_LARGE, OMEGA_MIN, STALL, MAX_ITER, PROX, SNAP_COMP,
    # SNAP_PLATEAU, PLATEAU, SNAP_COMP_LARGE, SNAP_PLATEAU_LARGE, LP_TOL_FAR, FAR_COMP, LP_TOL_NEAR,
    # LEAST_SLACK_SUPPORT, START_FACTORS, START_FACTORS_LARGE, START_FACTORS_ONE_ROUND_3D and GRACE
    assert (DEFAULT.large_omega_2d, DEFAULT.large_omega_3d, DEFAULT.large_omega_one_round,
            DEFAULT.large_omega_min, DEFAULT.large_stall, DEFAULT.large_max_iter) == (1.0, 0.5, 0.5, 0.125, 16, 300)
    assert (DEFAULT.large_prox, DEFAULT.large_snap_comp, DEFAULT.large_snap_plateau, DEFAULT.large_plateau,
            DEFAULT.large_snap_comp_very_large, DEFAULT.large_snap_plateau_very_large) == (0.03, 1e-3, 1e-2, 4, 1e-4, 1e-3)
    assert (DEFAULT.large_lp_tol_far, DEFAULT.large_far_comp, DEFAULT.large_lp_tol_near_2d,
            DEFAULT.large_least_slack_support, DEFAULT.large_grace) == (1e-4, 1e-2, 1e-7, 1e-6, 0.0)
    assert DEFAULT.large_start_factors == (1.0, 0.5, 0.25)
    assert DEFAULT.large_stall_very_large == 8  # large_stall's value before the wall family asked for 16
    assert DEFAULT.large_start_factors_very_large == (0.5, 0.4)
    assert DEFAULT.large_start_factors_one_round_3d == (0.5, 0.25, 1.0)


def test_a_tuple_setting_is_parsed_and_checked():
    """A tuple setting (the large route's start factors) is given on the command line as numbers
    separated by commas; an empty tuple, a factor not above 0 or a word is rejected naming it.
    large_grace alone among the floats may be 0."""
    assert settings.parse("large_start_factors=0.5, 0.4") == ("large_start_factors", (0.5, 0.4))
    assert DEFAULT.replace(large_start_factors=[1, 0.5]).large_start_factors == (1.0, 0.5)
    for bad in ((), (0.5, 0.0), ("a",)):
        with pytest.raises(ValueError, match="large_start_factors"):
            DEFAULT.replace(large_start_factors=bad)
    with pytest.raises(ValueError, match="large_start_factors"):
        settings.parse("large_start_factors=0.5,x")
    assert DEFAULT.replace(large_grace=0.0).large_grace == 0.0
    with pytest.raises(ValueError, match="large_omega_min"):
        DEFAULT.replace(large_omega_min=0.0)


# -- overrides: Options ------------------------------------------------------------------------


def test_options_take_a_mapping_or_a_settings():
    assert limit.Options().settings is DEFAULT
    o = limit.Options(settings={"large_min_free": 7, "tol_comp": 1e-5})
    assert o.settings.large_min_free == 7 and o.settings.tol_comp == 1e-5 and o.settings.tol_eq == 1e-6
    assert o.settings.changed() == {"large_min_free": 7, "tol_comp": 1e-5}
    s = dataclasses.replace(DEFAULT, global_max_blocks=3)
    assert limit.Options(settings=s).settings is s
    assert DEFAULT.replace(global_max_blocks=3) == s
    assert limit.Options(settings={"nlp_time_budget": 10}).settings.nlp_time_budget == 10.0  # an int for a float


@pytest.mark.parametrize("bad,words", [
    ({"large_min_fre": 100}, ["'large_min_fre'", "large_min_free", "tol_comp"]),  # the valid ones listed
    ({"large_min_free": 1.5}, ["'large_min_free'", "int"]),
    ({"large_min_free": "100"}, ["'large_min_free'", "int"]),
    ({"also_iterative": 1}, ["'also_iterative'", "bool"]),
    ({"tol_comp": "tight"}, ["'tol_comp'", "float"]),
    ({"tol_comp": -1e-6}, ["'tol_comp'", "> 0"]),
    ({"global_max_blocks": -1}, ["'global_max_blocks'", ">= 0"]),
])
def test_a_bad_name_or_value_is_a_value_error_naming_the_key(bad, words):
    with pytest.raises(ValueError) as exc:
        limit.Options(settings=bad)
    for w in words:
        assert w in str(exc.value)


def test_the_settings_survive_the_assembly():
    P = assemble(load_scene(_wall()), limit.Options(n_slide=None, settings={"large_min_free": 3}))
    assert settings.of(P).large_min_free == 3
    assert settings.of(object()) is DEFAULT


@pytest.mark.slow  # about 3-5 s: step 2 twice on a wall, both routes
def test_the_large_route_threshold_sends_a_small_scene_to_the_large_route():
    """10 free blocks: below the default large_min_free (200) step 2 runs the successive LP (SLSQP
    and SLA) besides the large route and reports route 'successive-lp'; with the threshold at 1
    free block, the large route alone ('iterative-lp')."""
    default = limit.analyse(_wall(), method="nlp")
    assert default.nlp.data["route"] == "successive-lp" and {"sla", "slsqp"} <= _solvers(default)
    large = limit.analyse(_wall(), method="nlp", options=limit.Options(settings={"large_min_free": 1}))
    assert large.nlp.status == "optimal" and large.nlp.data["route"] == "iterative-lp"
    assert _solvers(large) == {"iterative-lp"}
    assert large.nlp.data["n_starts"] == 3


def test_the_solver_thresholds_and_the_route_switch_are_read_from_the_settings():
    """slsqp_max_vars 0: no problem is small enough for SLSQP; also_iterative off: no large route
    below large_min_free. What is left is the successive LP alone."""
    r = limit.analyse(_wall(), method="nlp", options=limit.Options(settings={"slsqp_max_vars": 0,
                                                                             "also_iterative": False}))
    assert r.nlp.status == "optimal" and _solvers(r) == {"sla"}


def test_a_check_tolerance_is_read_from_the_settings():
    """An equilibrium tolerance of 1e-30 is below the rounding of any solver's answer on a wall:
    every LP answer fails its check, naming the equilibrium residual and that limit."""
    r = limit.analyse(_wall(), method="lp", options=limit.Options(settings={"tol_eq": 1e-30}))
    assert r.lp.status == "failed"
    assert all("equilibrium residual" in a["reason"] and "1e-30" in a["reason"] for a in r.lp.data["attempts"])
    assert limit.analyse(_wall(), method="lp").lp.status == "optimal"


def test_the_lp_solver_threshold_is_read_from_the_settings():
    small = load_scene(B.single_block(dim=2))
    assert lpmod.resolve("auto", assemble(small)) == "clarabel"
    assert lpmod.resolve("auto", assemble(small, limit.Options(settings={"lp_ipm_min_dof": 0}))) == "ipm"


def test_the_global_check_size_limit_is_read_from_the_settings():
    from limit import step2
    from limit.analysis import solve_lp
    from limit.results.typed import StepResult
    from limit.solve.status import Status

    P = assemble(load_scene(_wall()), limit.Options(settings={"global_max_blocks": 2}))
    sol, _, _ = solve_lp(P)
    part = StepResult(Status.FAILED, reason="stand-in")
    assert step2._independent(P, sol, part, sol.alpha, True, False, 1.0)["global"] == {
        "status": "skipped", "reason": "10 free blocks > 2"}
    assert "global" not in part  # a new part: the argument unchanged


# -- the command line --------------------------------------------------------------------------


@pytest.mark.slow  # about 2-3 s: limit solve end to end
def test_cli_set_overrides_a_setting_end_to_end(tmp_path, capsys):
    scene = tmp_path / "wall.json"
    scene.write_text(json.dumps(_wall()))
    out = tmp_path / "out.json"
    assert cli.main(["solve", str(scene), "--method", "nlp", "--no-cache", "--json", str(out),
                     "--set", "large_min_free=1"]) == 0
    assert json.loads(out.read_text())["nlp"]["route"] == "iterative-lp"
    assert cli.main(["solve", str(scene), "--method", "nlp", "--no-cache", "--json", str(out),
                     "--set", "also_iterative=false", "--set", "slsqp_max_vars=0"]) == 0
    assert {r["solver"] for r in json.loads(out.read_text())["nlp"]["runs"]} == {"sla"}


@pytest.mark.parametrize("item,words", [
    ("large_min_fre=1", ["'large_min_fre'", "valid:", "large_min_free"]),
    ("large_min_free=many", ["'large_min_free'", "int", "'many'"]),
    ("also_iterative=perhaps", ["'also_iterative'", "bool"]),
    ("tol_comp=0", ["'tol_comp'", "> 0"]),
    ("tol_comp", ["NAME=VALUE"]),
])
def test_cli_set_rejects_a_bad_item_with_exit_2_naming_the_key(item, words, capsys):
    assert cli.main(["solve", ROCKING, "--no-cache", "--set", item]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and len(err.strip().splitlines()) == 1
    for w in words:
        assert w in err


def test_cli_lists_every_setting_with_default_and_unit(capsys):
    assert cli.main(["settings"]) == 0
    text = capsys.readouterr().out
    for f in dataclasses.fields(Settings):
        line = next(ln for ln in text.splitlines() if ln.strip().startswith(f"{f.name} = "))
        assert repr(f.default) in line and f.metadata["unit"] in line


# -- the result cache --------------------------------------------------------------------------


@pytest.fixture
def cache_on(monkeypatch):
    monkeypatch.delenv("LIMIT_NO_CACHE", raising=False)  # tests/conftest.py sets it


def _key(argv):
    args = cli._parser().parse_args(["solve", ROCKING] + argv)
    opts = limit.Options(settings=cli.settings_of_args(args))
    return cli._solve_cache(args, load_scene(ROCKING), {}, opts.settings)[1]


def test_the_cache_key_holds_the_settings_that_differ_from_the_defaults(cache_on):
    plain = _key([])
    assert _key(["--set", "tol_gap=1e-5"]) != plain
    assert _key(["--set", "tol_gap=1e-5"]) != _key(["--set", "tol_gap=2e-5"])
    assert _key(["--set", "large_min_free=200"]) == plain  # the default value: the same run


def test_a_changed_setting_never_returns_a_result_cached_with_other_settings(tmp_path, capsys, cache_on):
    scene = tmp_path / "wall.json"
    scene.write_text(json.dumps(_wall()))
    run = ["solve", str(scene), "--method", "lp", "--cache", str(tmp_path / "cache")]
    assert cli.main(run) == 0
    assert "from the result cache" not in capsys.readouterr().err
    assert cli.main(run + ["--set", "tol_eq=1e-30"]) == 1  # solved again: its LP fails the check
    assert "from the result cache" not in capsys.readouterr().err
    assert cli.main(run + ["--set", "tol_gap=2e-6"]) == 0
    assert "from the result cache" not in capsys.readouterr().err
    assert cli.main(run) == 0
    assert "from the result cache" in capsys.readouterr().err


# -- one TOL_COMP; the documentation -----------------------------------------------------------


def test_one_tol_comp_in_the_library():
    """The check's complementarity limit is defined once (limit/solve/verify.py, from the
    settings); the successive LP's stopping target, a different quantity, has its own name."""
    defs = [(p.relative_to(ROOT).as_posix(), ln.strip()) for p in sorted((ROOT / "limit").rglob("*.py"))
            for ln in p.read_text().splitlines() if re.match(r"\s*TOL_COMP\s*[:=]", ln)]
    assert defs == [("limit/solve/verify.py", "TOL_COMP = DEFAULT.tol_comp")]
    literal = [p.name for p in (ROOT / "limit").rglob("*.py") if re.search(r"COMP\w*\s*=\s*1e-[67]\b", p.read_text())]
    assert literal == []  # no second complementarity limit as a bare number
    assert DEFAULT.sla_comp_target < DEFAULT.tol_comp


def test_docs_list_exactly_the_settings():
    doc = (ROOT / "docs" / "settings.md").read_text()
    table = doc.split("<!-- settings table -->\n", 1)[1].split("\n<!-- end settings table -->", 1)[0]
    assert table == settings.markdown_table(), "docs/settings.md: paste limit.settings.markdown_table() again"
    names = re.findall(r"^\| `(\w+)` \|", table, flags=re.M)
    assert names == [f.name for f in dataclasses.fields(Settings)]
    assert "limit/settings.py" in (ROOT / "CONTRIBUTING.md").read_text()
