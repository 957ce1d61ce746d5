"""The validation run and its report: contents checked against the results table, caching,
and DEM faults shown as failures while the run goes on."""
import contextlib
import io
import json
import re

import pandas as pd
import pytest

from reports import render, table
from reports.validate import main as validate_main

SCENES = ["block-rocking-2d", "portal-2d", "paper-fig5-trilithic-3d"]


@pytest.fixture(scope="module")
def run(tmp_path_factory, monkeypatch_module):
    tmp = tmp_path_factory.mktemp("validate")
    monkeypatch_module.setenv("DEM_YADE", str(tmp / "no-such-yade"))  # every DEM run fails: YADE missing
    args = ["--only", *SCENES, "--cache", str(tmp / "cache"), "--out", str(tmp / "out"), "--jobs", "2",
            "--no-progress", "--no-lmgc"]
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = validate_main(args)
    (tmp / "stderr.txt").write_text(err.getvalue())
    return tmp, args, code


@pytest.fixture(scope="module")
def monkeypatch_module():
    mp = pytest.MonkeyPatch()
    yield mp
    mp.undo()


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_run_completes_and_writes_everything(run):
    """Every DEM stage failed (YADE missing): the run still writes everything, lists each failed
    stage at the end and exits with status 1; without the DEM nothing failed, and the status is 0."""
    tmp, args, code = run
    assert code == 1
    listed = re.findall(r"validate: FAILED (\S+) (\S+): (.*)", (tmp / "stderr.txt").read_text())
    assert sorted((n, st) for n, st, _ in listed) == sorted((n, "dem") for n in SCENES)
    assert all("not found" in why for _, _, why in listed)
    assert f"({len(SCENES)} scenes, {len(SCENES)} with a failed stage, {len(SCENES)} failed stages" in (
        tmp / "stderr.txt").read_text()  # the summary counts what the exit status and the list say
    again = list(args)
    again[again.index("--out") + 1] = str(tmp / "out-no-dem")  # the other tests read the first report
    with contextlib.redirect_stderr(io.StringIO()):
        assert validate_main(again + ["--no-dem"]) == 0  # the LA stages come from the cache
    out = tmp / "out"
    for f in ("index.html", "index.md", "results.csv", "results.parquet", "figures/alpha.png",
              "figures/time_error.png", "figures/portal-2d.png", "vtk/portal-2d.vtk"):
        assert (out / f).exists(), f


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_table_matches_cached_results(run):
    tmp, _, _ = run
    df = pd.read_csv(tmp / "out" / "results.csv")
    pq = pd.read_parquet(tmp / "out" / "results.parquet")
    assert list(df.name) == SCENES == list(pq.name)
    for name in SCENES:
        la = json.loads(next((tmp / "cache" / "la").glob(f"{name}-*.json")).read_text())
        r = df[df.name == name].iloc[0]
        assert r.lp_alpha == pytest.approx(la["lp"]["alpha"], rel=1e-12)
        assert r.lp_status == la["lp"]["status"] == "optimal"
        exp = json.loads(open(f"scenes/catalog/{name}.json").read()).get("expected")
        if exp:
            assert r.ref_alpha == pytest.approx(exp["alpha"])
            assert abs(r.lp_err) < 1e-6
        else:
            assert pd.isna(r.ref_alpha)


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_report_shows_every_scene_and_its_numbers(run):
    tmp, _, _ = run
    df = pd.read_csv(tmp / "out" / "results.csv")
    html = (tmp / "out" / "index.html").read_text()
    md = (tmp / "out" / "index.md").read_text()
    for _, r in df.iterrows():
        assert f'id="{r["name"]}"' in html and f"## {r['name']}" in md
        assert format(r.lp_alpha, ".4g") in html
        assert format(r.lp_alpha, ".4g") in md


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_published_value_beside_ours_with_the_reason(run):
    """The paper's Fig. 5 gives alpha = 0.086 (LP): the table carries it and the difference
    from our LP, the report shows it with the scene's explanation."""
    tmp, _, _ = run
    df = pd.read_csv(tmp / "out" / "results.csv")
    r = df[df.name == "paper-fig5-trilithic-3d"].iloc[0]
    meta = json.loads(open("scenes/catalog/paper-fig5-trilithic-3d.json").read())["meta"]["published"]
    assert r.pub_alpha == meta["alpha"] == 0.086
    assert r.pub_diff == pytest.approx(r.lp_alpha / 0.086 - 1, rel=1e-9)
    for text in ((tmp / "out" / "index.html").read_text(), (tmp / "out" / "index.md").read_text()):
        assert "Published: alpha = 0.086 (LP)" in text
        assert meta["note"][:60] in text.replace("&#x27;", "'")


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_dem_fault_is_failed_in_red_and_not_cached(run):
    tmp, args, _ = run
    df = pd.read_csv(tmp / "out" / "results.csv")
    opted_out = {n for n in SCENES
                 if not ((json.loads(open(f"scenes/catalog/{n}.json").read()).get("meta") or {}).get("dem") or {})
                 .get("run", True)}
    assert opted_out == set()  # every catalog scene runs the DEM in make validate
    ran = df[~df.name.isin(opted_out)]
    assert set(ran.dem_status) == {"failed"}
    assert all("yade" in str(x).lower() for x in ran.dem_reason)
    html = (tmp / "out" / "index.html").read_text()
    assert len(re.findall(r'<td class="failed">failed</td>', html)) == len(ran)
    assert "**failed**" in (tmp / "out" / "index.md").read_text()
    # failures are retried next time, never cached
    assert not list((tmp / "cache").glob("dem/*.json"))
    # ... but each failure is kept whole for diagnosis, and the run's log says where
    kept = sorted((tmp / "cache" / "failed" / "dem").glob("*.json"))
    assert sorted(p.name.rsplit("-", 2)[0] for p in kept) == sorted(ran.name)
    log = (tmp / "stderr.txt").read_text()
    for p in kept:
        res = json.loads(p.read_text())
        assert res["status"] == "failed" and "yade" in res["reason"].lower()
        assert str(p) in log


@pytest.mark.slow  # the validation run end to end (its module fixture: about 30 s)
def test_cache_reused_and_changed_scene_recomputed(run, tmp_path, capsys):
    tmp, args, _ = run
    from reports.cache import Cache
    from reports.validate import plan
    from scenes.catalog import CATALOG_DIR

    files = [CATALOG_DIR / f"{n}.json" for n in SCENES]
    done, todo = plan(files, ["la"], Cache(tmp / "cache"), fresh=False)
    assert len(done) == len(SCENES) and not todo
    changed = tmp_path / "portal-2d.json"
    d = json.loads(files[1].read_text())
    d["friction"] = 0.95
    changed.write_text(json.dumps(d))
    done, todo = plan([files[0], changed], ["la"], Cache(tmp / "cache"), fresh=False)
    assert [t[1] for t in todo] == ["portal-2d"] and len(done) == 1


def test_failed_lp_is_red():
    row = {"name": "x", "title": "", "figure": "", "dim": 2, "n_blocks": 2, "n_interfaces": 1, "ref_alpha": None,
           "ref_kind": None, "ref_source": "", "lp_status": "failed", "lp_alpha": None, "lp_reason": "boom",
           "nlp_status": "skipped", "nlp_alpha": None, "nlp_reason": "", "global_status": None,
           "global_alpha": None, "iter_status": None, "iter_alpha": None, "fric_alpha": None,
           "dem_status": "collapsed", "dem_alpha": 0.3, "dem_reason": "", "dem_uncertainty": 0.01,
           "lp_err": float("nan"), "nlp_err": float("nan"), "dem_vs_la": float("nan"), "lp_time_s": 0.1,
           "nlp_time_s": None, "dem_time_s": 10.0, "mech_similarity": float("nan"), "mech_kind": "lp"}
    df = pd.DataFrame([row])
    html = render.catalog_html(df, stamp="now")
    assert '<td class="failed">failed</td>' in html
    assert any("The LP failed: boom" in s for s in render.explain(df.iloc[0]))


def test_similarity_is_scale_free():
    from limit.model.scene import load_scene
    from scenes import builders as B

    s = load_scene(B.stack(2, dim=2))
    m = {"s0": [0.1, 0.0, -0.2], "s1": [0.3, 0.05, -0.2]}
    assert table.similarity(s, m, {k: [10 * x for x in v] for k, v in m.items()}) == pytest.approx(1.0)
    assert table.similarity(s, m, {k: [-x for x in v] for k, v in m.items()}) == pytest.approx(-1.0)
    assert table.similarity(s, m, None) != table.similarity(s, m, None)  # nan


@pytest.mark.lmgc90
def test_failure_copy_that_cannot_be_written_does_not_stop_the_run(tmp_path, monkeypatch, capsys):
    from reports.cache import Cache

    def full_disk(*a, **k):
        raise OSError("No space left on device")

    monkeypatch.setattr(Cache, "put_failed", full_disk)
    monkeypatch.setenv("DEM_YADE", str(tmp_path / "no-such-yade"))
    code = validate_main(["--only", "block-rocking-2d", "--cache", str(tmp_path / "cache"), "--out",
                          str(tmp_path / "out"), "--jobs", "1", "--no-progress"])
    assert code == 1  # the DEM stage failed
    assert "full result not kept: No space left on device" in capsys.readouterr().err
    df = pd.read_csv(tmp_path / "out" / "results.csv")
    assert list(df.dem_status) == ["failed"] and list(df.lp_status) == ["optimal"]
    # LMGC90 is part of the default run (b/h = 0.3: the block rocks at 0.3)
    from dem_validation.engines.lmgc90.lmgc_main import knobs

    assert list(df.lmgc_status) == ["collapsed"] and abs(df.lmgc_alpha[0] / 0.3 - 1) < knobs({})["alpha_rtol"]


def test_dem_opt_out_is_reported_as_skipped_with_its_reason():
    """A user's scene may still opt out of the DEM (``meta.dem.run: false``); the catalog
    no longer does (test_dem_fault_is_failed_in_red_and_not_cached)."""
    from reports.stages import dem_options, run_dem

    opts = dem_options({"meta": {"dem": {"run": False, "reason": "too large for this machine"}}})
    res = run_dem("unused.json", opts)
    assert res["status"] == "skipped" and res["alpha"] is None and res["reason"] == "too large for this machine"


def test_capacity_curve_points_follow_the_load_order():
    """Bisection visits alphas out of order (0.2, then 0.4 collapses, then 0.3 holds): the
    curve is the equilibria sorted by load, per stiffness, and the first collapse is the
    lowest collapsing alpha; a re-stiffening record is not a point of the curve."""
    from reports.plots import capacity_figure, capacity_points

    hist = [{"eps": 1e-5, "phase": "settle", "alpha": 0.0, "outcome": "stable", "control": 0.0},
            {"eps": 1e-5, "phase": "load", "alpha": 0.2, "outcome": "stable", "control": 1e-4},
            {"eps": 1e-5, "phase": "load", "alpha": 0.4, "outcome": "collapse", "control": 9e-3},
            {"eps": 1e-5, "phase": "bisect", "alpha": 0.3, "outcome": "stable", "control": 2e-4},
            {"eps": 1e-5, "phase": "bisect", "alpha": 0.35, "outcome": "collapse", "control": 8e-3},
            {"eps": 2e-6, "phase": "re-stiffen", "alpha": 0.2, "outcome": "stable", "control": 1e-4}]
    pts = capacity_points({"history": hist})
    u, a = pts["curves"][1e-5]
    assert list(a) == [0.0, 0.2, 0.3] and list(u) == [0.0, 1e-4, 2e-4]
    assert pts["collapse"] == {1e-5: 0.35} and 2e-6 not in pts["curves"]
    assert not capacity_figure({"history": []}, 0.3, "unused.png")  # nothing to draw: no figure


def test_capacity_figure_draws_lmgc90_trials_without_yade(tmp_path):
    """LMGC90's trials (eps 0, rigid) are a curve of their own: a figure is drawn from them
    alone, and only from an LMGC90 result (a YADE-like dict passed as lmgc draws nothing)."""
    from reports.plots import capacity_figure, capacity_points

    hist = [{"eps": 0.0, "phase": "settle", "alpha": 0.0, "outcome": "stable", "control": 1e-7},
            {"eps": 0.0, "phase": "load", "alpha": 0.29, "outcome": "stable", "control": 2e-6},
            {"eps": 0.0, "phase": "load", "alpha": 0.31, "outcome": "collapse", "control": 3e-4}]
    lm = {"engine": "lmgc90", "status": "collapsed", "alpha": 0.3, "history": hist}
    u, a = capacity_points(lm)["curves"][0.0]
    assert list(a) == [0.0, 0.29] and list(u) == [1e-7, 2e-6]
    assert capacity_figure(None, 0.3, tmp_path / "c.png", lmgc=lm) and (tmp_path / "c.png").stat().st_size > 0
    assert not capacity_figure(None, 0.3, tmp_path / "d.png", lmgc={**lm, "engine": "yade"})


def test_dem_below_the_nlp_points_at_a_lower_iterative_lp_value():
    """Fig. 3 with 70 stones, measured: LP = NLP = 0.5708 (the NLP stayed at its associative
    start), the iterative LP 0.5230, the DEM 0.5012. The text must name the iterative LP's
    value and the DEM's distance from it: 0.5012 / 0.5230 - 1 = -4.2 %."""
    from reports.render import dem_disagreement

    row = {"lp_alpha": 0.5708, "fric_alpha": 0.5708, "dem_alpha": 0.5012, "iter_alpha": 0.5230}
    txt = dem_disagreement(row)
    assert "0.523" in txt and "local minimum" in txt and "-4.2 %" in txt
    # without an iterative LP value below the NLP, the other explanation
    txt = dem_disagreement(dict(row, iter_alpha=0.5708))
    assert "local minimum" not in txt and "contact model" in txt


def test_dem_model_text_says_how_the_rounding_was_treated():
    """An extrapolated result is corrected for the corner rounding; the stiffest run taken
    as it is (runs with no trend, Fig. 5) is not, and the text must not claim it."""
    from reports.table import dem_model_text

    runs = [{"alpha": 0.0862, "eps": 2.5e-6, "sphere_radius": 5e-4},
            {"alpha": 0.0835, "eps": 6.25e-7, "sphere_radius": 1.3e-4}]
    plain = dem_model_text({"runs": runs, "extrapolation": {"method": "stiffest run (no trend with the stiffness)"},
                            "note": "not extrapolated: the stiffer run collapsed 3.1 % earlier"})
    assert "corrected for the rounding" not in plain and "taken as it is" in plain and "Not extrapolated" in plain
    fitted = dem_model_text({"runs": runs, "extrapolation": {"method": "richardson"}})
    assert "corrected for the rounding" in fitted and "taken as it is" not in fitted


@pytest.mark.parametrize("deg", [0.0, pytest.param(45.0, marks=pytest.mark.slow)])  # about 2 s each
def test_friction_model_stage_beside_the_papers(tmp_path, deg):
    """A squat 1 x 1 x 0.5 block (mu = 0.4) slides under a horizontal load at ``deg`` to x.
    Coulomb's circular cone gives alpha = mu in every direction. The paper's 4 faces
    |V.e_x| <= mu N, |V.e_y| <= mu N give mu / max(|cos|, |sin|): 0.4 along x, 0.4 sqrt 2
    at 45 deg (41 % too strong). 24 inscribed faces d_j.V <= cos(pi/24) mu N, d_j at
    multiples of 15 deg, give mu cos(pi/24) along any d_j (both 0 and 45 deg are)."""
    import math

    from reports.render import cone_lines
    from reports.stages import cone_options, la_options, run_cone, run_la
    from reports.table import row
    from scenes import builders as B

    data = B.single_block(dim=3, b=1.0, h=0.5, t=1.0, mu=0.4, name="squat")
    th = math.radians(deg)
    data["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    path = tmp_path / "squat.json"
    path.write_text(json.dumps(data))
    la, cone = run_la(str(path), la_options(data)), run_cone(str(path), cone_options(data))
    paper = 0.4 / max(abs(math.cos(th)), abs(math.sin(th)))
    assert la["lp"]["alpha"] == pytest.approx(paper, rel=1e-6)
    assert cone["lp"]["alpha"] == pytest.approx(0.4 * math.cos(math.pi / 24), rel=1e-6)
    r = row(path, la, None, None, cone)
    assert r["cone_alpha"] == pytest.approx(0.4 * math.cos(math.pi / 24), rel=1e-6)
    assert "24 inscribed faces" in cone_lines(r)[0] and f"{r['cone_alpha']:.4g}" in cone_lines(r)[0]


def test_friction_model_stage_skips_2d_scenes():
    from reports.stages import cone_options, run_cone

    res = run_cone("unused.json", cone_options({"dim": 2}))
    assert res["lp"]["status"] == "skipped" and "2D" in res["lp"]["reason"]


def test_engines_table_shows_numbers_and_statuses():
    """One row per scene; a stage without a number shows why (dead-load collapse, its status)."""
    rows = [{"name": "a", "dim": 2, "n_free": 1, "lp_alpha": 0.3, "fric_alpha": 0.3, "cone_alpha": None,
             "cone_status": "skipped", "dem_alpha": 0.3005, "dem_vs_la": 0.0017, "dem_time_s": 3.0,
             "lmgc_alpha": 0.30009, "lmgc_vs_la": 0.0003, "lmgc_time_s": 4.0},
            {"name": "b", "dim": 2, "n_free": 5, "lp_alpha": None, "lp_status": "infeasible", "fric_alpha": None,
             "nlp_status": None, "dem_alpha": None, "dem_dead": True, "dem_status": "collapsed",
             "lmgc_alpha": None, "lmgc_status": "skipped", "lmgc_dead": False}]
    text = table.engines_markdown(pd.DataFrame(rows))
    assert text.startswith("Dynamic collapses below the frictional limit analysis (by more than 1 %): 0 of 1 ")
    lines = [ln for ln in text.strip().splitlines() if ln.startswith("|")]
    assert len(lines) == 4 and lines[0].startswith("| scene |")
    assert "| 0.30009 | +0.03% |" in lines[2] and "| skipped |" in lines[2]
    assert "| infeasible |" in lines[3] and "dead-load collapse" in lines[3] and lines[3].count("skipped") == 1


def test_lmgc_stage_cost_limit_and_its_lifting(tmp_path):
    """A scene whose measured LMGC90 cost (meta.lmgc.cost_s) exceeds LMGC_BUDGET_S is
    skipped by the default validation with the reason; --lmgc-all (budget None) runs it, and
    a default plan shows a cached --lmgc-all result instead of the skip."""
    from reports.cache import Cache, key
    from reports.stages import LMGC_BUDGET_S, lmgc_options, run_lmgc
    from reports.validate import plan

    data = {"name": "costly", "blocks": [{"fixed": True}, {}], "meta": {"lmgc": {"cost_s": LMGC_BUDGET_S + 1}}}
    opts = lmgc_options(data)
    assert not opts["run"] and f"{LMGC_BUDGET_S + 1:.0f} s" in opts["reason"] and "--lmgc-all" in opts["reason"]
    res = run_lmgc("unused.json", opts)
    assert res["status"] == "skipped" and res["reason"] == opts["reason"]
    assert lmgc_options(data, budget_s=None)["run"]
    assert lmgc_options({"blocks": [{"fixed": True}, {}]})["run"]  # no measured cost: runs
    cheap = {**data, "meta": {"lmgc": {"cost_s": LMGC_BUDGET_S}}}
    assert lmgc_options(cheap)["run"]
    f = tmp_path / "costly.json"
    f.write_text(json.dumps(data))
    cache = Cache(tmp_path / "cache")
    done, todo = plan([f], ["lmgc"], cache, fresh=False)
    assert not done and todo[0][4]["run"] is False
    full = lmgc_options(data, budget_s=None)
    cache.put("lmgc", "costly", key("lmgc", data, full), {"status": "collapsed", "alpha": 0.5, "engine": "lmgc90"})
    done, todo = plan([f], ["lmgc"], cache, fresh=False)
    assert not todo and done[("costly", "lmgc")]["alpha"] == 0.5


def test_lmgc_disagreement_names_the_known_causes():
    """Over 2 % from the frictional LA, the report says why: between NLP and LP (rigid
    contacts keep friction engaged), below it with a creeping dead-load trial (time-step
    dependent, not a check), and whether YADE departs the same way."""
    from reports.render import lmgc_lines

    base = {"lmgc_status": "collapsed", "lp_alpha": 1.0, "fric_alpha": 0.357, "dem_alpha": 0.38, "mech_kind": "nlp"}
    between = lmgc_lines({**base, "lmgc_alpha": 0.383, "lmgc_vs_la": 0.383 / 0.357 - 1})
    assert len(between) == 2 and "not unique" in between[1] and "YADE agrees" in between[1]
    creep = lmgc_lines({**base, "lp_alpha": 0.176, "fric_alpha": 0.161, "dem_alpha": 0.164, "lmgc_alpha": 0.125,
                        "lmgc_vs_la": 0.125 / 0.161 - 1, "lmgc_creep": True})
    assert "creep" in creep[1] and "not a check" in creep[1] and "YADE agrees" not in creep[1]
    close = lmgc_lines({**base, "lmgc_alpha": 0.36, "lmgc_vs_la": 0.36 / 0.357 - 1})
    assert len(close) == 1  # within 2 %: no explanation needed


@pytest.mark.slow  # about 5 s: step 2 on three catalog scenes and the report's worked example
def test_worked_example_states_demand_formulas_and_verdicts(tmp_path):
    """The report's verdicts: the catalog scenes stating a demand (the 3D out-of-plane wall
    and the 2D portal, ag = 0.2 g, S = 1.2, q = 2: ag S / q = 0.2 9.81 1.2 / 2 = 1.1772 m/s^2 by
    hand) get their linear and nonlinear checks, with numbers equal to the library's
    (limit.verdict.kinematic_check on the LA's mechanism); a scene without a demand gets none."""
    from limit.analysis import analyse
    from limit.verdict.kinematic_check import linear
    from limit.model.scene import load_scene
    from reports import plots, verdict
    from tests.conftest import ROOT

    by_name, results = {}, {}
    for name in ("wall-out-of-plane-3d", "portal-2d", "block-rocking-2d"):
        path = ROOT / "scenes" / "catalog" / f"{name}.json"
        by_name[name] = path
        results[(name, "la")] = analyse(load_scene(path), method="auto").data
    assert "verdict" not in results[("block-rocking-2d", "la")]
    text = "\n".join(verdict.worked_example(results, by_name))
    assert "ag = 0.2 g" in text and "C8A.4.9" in text and "against 1.1772 m/s^2" in text
    assert "block-rocking-2d" not in text
    scene = load_scene(by_name["wall-out-of-plane-3d"])
    step, a0, mech = verdict.la_mechanism(results[("wall-out-of-plane-3d", "la")])
    q = linear(scene, mech, a0, 1.35)
    assert f"a0* = {q['a0_star']:.4f} m/s^2" in text and f"e* = {q['e_star']:.4f}" in text
    # both scenes, and the 3D wall again with its base above ground (the 2019 floor spectrum)
    assert text.count("Linear check") == 3 and text.count("Nonlinear check: du*") == 3
    assert text.count("above ground** (illustrative") == 1 and "SDeZ(T_SLV) (the floor spectrum at Z" in text
    portal = load_scene(by_name["portal-2d"])
    kin = verdict.kinematic_curve(portal, results[("portal-2d", "la")])
    assert kin is not None and kin["alpha"][0] == pytest.approx(0.2, rel=1e-6) and kin["d0"] > 0
    assert plots.capacity_figure(None, 0.2, tmp_path / "k.png", kinematic=kin)
    assert verdict.worked_example({}, by_name) == []  # no LA result: no example


def test_stages_start_longest_first_by_measured_cost():
    """The validation orders every stage by its expected cost: a measured meta.<stage>.cost_s
    wins over the size estimate (Fig. 5: 17 blocks, 295 s of YADE), and an unmeasured stage
    falls back to its size."""
    from reports.validate import dem_cost, stage_cost

    small_but_slow = {"dim": 3, "blocks": [{}] * 17, "meta": {"dem": {"cost_s": 295.0}}}
    big_but_quick = {"dim": 2, "blocks": [{"vertices": [[0, 0]] * 8}] * 70}
    assert stage_cost("dem", small_but_slow) == 295.0
    assert dem_cost(big_but_quick) == 560.0  # 70 blocks of 8 vertex spheres
    assert stage_cost("dem", big_but_quick) == pytest.approx(0.45 * 560.0)  # DEM_S_PER_SPHERE
    assert stage_cost("la", big_but_quick) == pytest.approx(7.0)
    assert stage_cost("lmgc", small_but_slow) == pytest.approx(0.14 * dem_cost(small_but_slow))  # unmeasured


def test_sweep_stage_and_its_report_section(tmp_path):
    """The ``sweep`` stage runs only for a 3D scene asking for it (meta.sweep); the report's
    section draws the polar plot and the mechanism at the minimum. A square block b x b x h
    has alpha(theta) = (b/h) / max(|cos|, |sin|) (tests/test_direction_sweep.py): minimum b/h = 0.3
    along an axis; with a demand, the code check is made there (only)."""
    import json

    from reports import worst_direction
    from reports.stages import run_sweep, sweep_options
    from scenes import builders as B

    data = dict(B.single_block(3, 0.3, 1.0, t=0.3, mu=0.8, name="sq"), meta={"sweep": {"step": 45}},
                demand={"ag_g": 0.2})
    path = tmp_path / "sq.json"
    path.write_text(json.dumps(data))
    res = run_sweep(str(path), sweep_options(data))
    assert res["status"] == "done" and len(res["theta"]) == 8
    assert res["min_alpha"] == pytest.approx(0.3, rel=1e-6) and res["min_theta"] % 90 == 0
    assert res["min_nlp"]["verdict"]["check"]["linear"]["capacity"] == pytest.approx(0.3 * 9.81 / 1.35, rel=1e-6)
    plain = {k: v for k, v in data.items() if k != "meta"}
    assert run_sweep(str(path), sweep_options(plain))["status"] == "skipped"
    figs = tmp_path / "figures"
    figs.mkdir()
    lines = worst_direction.section({("sq", "sweep"): res}, {"sq": path}, figs)
    text = "\n".join(lines)
    assert "minimum LP alpha 0.3 at" in text and "![worst load direction of sq](figures/sq-sweep.png)" in text
    assert (figs / "sq-sweep.png").stat().st_size > 0 and (figs / "sq-sweep-mechanism.png").stat().st_size > 0
    assert worst_direction.section({}, {"sq": path}, figs) == []


@pytest.mark.slow  # about 10 s: step 2 in 8 directions
def test_a_sweep_scene_may_ask_for_step_2_in_every_direction(tmp_path):
    """meta.sweep.frictional: the sweep stage runs step 2 in every direction. The block of
    test_frictional_sweep_runs_step_2_in_every_direction (b = 0.3, t = 0.8, h = 1, mu 0.5), every
    90 degrees: it overturns at b/h = 0.3 along +-x and slides at mu = 0.5 along +-y (overturning
    there needs t/h = 0.8), so the frictional minimum is 0.3 along x, and the section says so."""
    import json

    from reports import worst_direction
    from reports.stages import run_sweep, sweep_options
    from scenes import builders as B

    data = dict(B.single_block(3, 0.3, 1.0, t=0.8, mu=0.5, name="bl"), meta={"sweep": {"step": 90, "frictional": True}})
    path = tmp_path / "bl.json"
    path.write_text(json.dumps(data))
    assert sweep_options(data)["frictional"] and not sweep_options({**data, "meta": {"sweep": {}}})["frictional"]
    res = run_sweep(str(path), sweep_options(data))
    assert res["status"] == "done" and res["alpha_frictional"] == pytest.approx([0.3, 0.5, 0.3, 0.5], rel=1e-5)
    figs = tmp_path / "figures"
    figs.mkdir()
    text = "\n".join(worst_direction.section({("bl", "sweep"): res}, {"bl": path}, figs))
    assert "step 2 in every direction: frictional minimum 0.3 at" in text


def test_lmgc_creep_is_a_held_trial_that_never_came_to_rest(tmp_path):
    """``lmgc_creep`` flags an LMGC90 run with a trial that held without coming to rest by
    speed (any trial: a search from a guess has no alpha = 0 trial): one that ran out its
    hold, or ended because its blocks rattled in place ("level"); a result cached before
    ``settled`` existed counts ``rest`` as the speed rule."""
    import json

    from reports.table import row
    from scenes import builders as B

    data = B.single_block(2, 0.3, 1.0, mu=0.8)
    path = tmp_path / "block.json"
    path.write_text(json.dumps(data))
    la = {"lp": {"status": "optimal", "alpha": 0.3}, "nlp": {"status": "skipped", "alpha": 0.3}}

    def lm(rest, **settled):
        return {"status": "collapsed", "alpha": 0.3, "history": [
            {"phase": "load", "alpha": 0.29, "outcome": "stable", "rest": rest, **settled},
            {"phase": "load", "alpha": 0.31, "outcome": "collapse", "rest": False, "settled": None}]}
    assert row(path, la, None, lm(False))["lmgc_creep"] is True
    assert row(path, la, None, lm(True))["lmgc_creep"] is False
    assert row(path, la, None, lm(True, settled="speed"))["lmgc_creep"] is False
    assert row(path, la, None, lm(True, settled="level"))["lmgc_creep"] is True
    assert row(path, la, None, lm(False, settled=None))["lmgc_creep"] is True


def test_time_error_figure_for_scenes_without_a_reference(tmp_path):
    """A run of scenes that have no reference alpha (e.g. ``--only`` one paper wall) has no
    point for the log-log figure; the report is still written (it raised "Data cannot be
    log-scaled" and lost the whole report after the stages had run)."""
    from reports import plots

    cols = {f"{m}_{k}": [v] for m in ("lp", "nlp", "dem") for k, v in (("time_s", 12.0), ("err", float("nan")))}
    path = tmp_path / "time_error.png"
    plots.time_error(pd.DataFrame(cols), path)
    assert path.stat().st_size > 0


def test_vtk_keeps_every_engine_and_carries_ids_loads_and_joint_states(tmp_path):
    """Two DEM result files (YADE's and LMGC90's) give two displacement fields, neither lost; the
    cells carry the block ids, the points each block's loads (the 0.3 x 1.0 m 2D block of 2000
    kg/m^3 weighs 0.3 x 1.0 x 1 m x 2000 x 9.81 = 5886 N, its live load along +x the same at
    alpha = 1), and the joints file the LP's state of the one joint (the block rocks: state 1)."""
    from limit.model.scene import load_scene
    from reports import vtk
    from scenes import builders as B

    scene_d = B.single_block(dim=2, b=0.3, h=1.0, name="blk")
    (tmp_path / "s.json").write_text(json.dumps(scene_d))
    bid = next(b["id"] for b in scene_d["blocks"] if not b.get("fixed"))
    lp = {"lp": {"status": "optimal", "alpha": 0.3, "mechanism": {bid: [1.0, 0.0, 0.0]},
                 "interfaces": {"rock": [0], "open": [], "slide": [], "twist": []}}}
    ya = {"dem": {"status": "collapsed", "engine": "yade", "displacement": {bid: [0.01, 0.0, -0.02]}}}
    lm = {"dem": {"status": "collapsed", "engine": "lmgc90", "displacement": {bid: [0.02, 0.0, -0.03]}}}
    files = []
    for k, d in enumerate((lp, ya, lm)):
        files.append(tmp_path / f"r{k}.json")
        files[-1].write_text(json.dumps(d))
    assert vtk.main([str(tmp_path / "s.json"), *map(str, files), "-o", str(tmp_path / "o.vtk")]) == 0
    text = (tmp_path / "o.vtk").read_text()
    for field in ("lp_mechanism", "yade_displacement", "lmgc90_displacement", "dead_load", "live_load"):
        assert f"VECTORS {field} double" in text, field
    n_cells = int(re.search(r"POLYGONS (\d+)", text).group(1))
    ids = text.split("block_id 1 ")[1].splitlines()
    assert int(ids[0].split()[0]) == n_cells and set(ids[1:1 + n_cells]) == {b["id"] for b in scene_d["blocks"]}
    s = load_scene(scene_d)
    free = next(b for b in s.blocks if not b.fixed)
    block = text.split("VECTORS dead_load double\n")[1].splitlines()
    k = [i for i, b in enumerate(s.blocks) if not b.fixed][0]
    first = sum(len(b.pieces[0].vertices) for b in s.blocks[:k])
    assert [float(x) for x in block[first].split()] == pytest.approx([0.0, -5886.0, 0.0], rel=1e-9)
    live = text.split("VECTORS live_load double\n")[1].splitlines()
    assert [float(x) for x in live[first].split()] == pytest.approx([5886.0, 0.0, 0.0], rel=1e-9)
    assert free.id == bid
    joints = (tmp_path / "o-joints.vtk").read_text()
    assert "LINES 1 3" in joints and "SCALARS lp_state int 1\nLOOKUP_TABLE default\n1\n" in joints
    assert "SCALARS nlp_state int 1\nLOOKUP_TABLE default\n0\n" in joints


def test_the_summary_counts_agreement_and_gives_each_other_result_one_linked_line():
    """Three scenes with YADE: one 1 % above step 2 (agrees), one 30 % above it and below the LP
    (between the bounds: the loading path), one 10 % below it (suspect low); LMGC90 on one, 8 %
    below with trials that crept. 1 of 4 collapses agrees within 5 %; three linked lines."""
    base = {"ref_alpha": None, "within_ref": None, "nlp_err": float("nan"), "ref_source": "", "lp_alpha": 0.5}
    rows = [dict(base, name="a", fric_alpha=0.3, dem_status="collapsed", dem_alpha=0.303, dem_vs_la=0.01,
                 dem_bracket="", lmgc_status=None, lmgc_alpha=None, lmgc_vs_la=None, lmgc_bracket=""),
            dict(base, name="b", fric_alpha=0.3, dem_status="collapsed", dem_alpha=0.39, dem_vs_la=0.3,
                 dem_bracket="", lmgc_status=None, lmgc_alpha=None, lmgc_vs_la=None, lmgc_bracket=""),
            dict(base, name="c", fric_alpha=0.3, dem_status="collapsed", dem_alpha=0.27, dem_vs_la=-0.1,
                 dem_bracket="suspect low", lmgc_status="collapsed", lmgc_alpha=0.276, lmgc_vs_la=-0.08,
                 lmgc_bracket="suspect low", lmgc_creep=True)]
    lines = render.summary_lines(pd.DataFrame(rows))
    assert lines[0]["text"].startswith("Dynamic engines: 1 of 4 collapses agree") and lines[0]["href"] is None
    linked = [(x["href"], x["text"]) for x in lines[1:]]
    assert [h for h, _ in linked] == ["b", "c", "c"]
    assert "between step 2 and the LP" in linked[0][1] and "YADE +30.00 %" in linked[0][1]
    assert "a contradiction" in linked[1][1] and "creep" in linked[2][1] and linked[2][1].startswith("LMGC90")
    html = render.catalog_html(pd.DataFrame(rows).assign(dim=2, n_blocks=2, n_interfaces=1, title="", figure="",
                                                         pub_alpha=None, lp_status="optimal", nlp_status="optimal",
                                                         nlp_alpha=0.3, global_status=None, global_alpha=None,
                                                         lp_err=float("nan"), lp_time_s=0.1, nlp_time_s=0.1,
                                                         dem_time_s=1.0, mech_similarity=float("nan")))
    assert '<a href="#c">c</a>: LMGC90 -8.00 %' in html
    rows[2].update(lmgc_creep=False, lmgc_dt="0.001 s: 0.25, 0.0005 s: 0.265, 0.00025 s: 0.276 (not converged)")
    moving = render.summary_lines(pd.DataFrame(rows))[-1]["text"]
    assert "still moved at its last halving of the time step" in moving and "0.00025 s: 0.276" in moving
    rows[2].update(lmgc_dt="0.001 s: 0.25, 0.0005 s: 0.27, 0.00025 s: 0.276 (converged)", lmgc_dt_rising=True)
    rising = render.summary_lines(pd.DataFrame(rows))[-1]["text"]
    assert "rose at every halving of the time step" in rising
    rows[2].update(lmgc_dt_rising=False)
    assert "a contradiction" in render.summary_lines(pd.DataFrame(rows))[-1]["text"]


def test_the_la_stage_carries_the_capacity_curve_the_report_draws():
    """The ``la`` stage follows its mechanism at finite displacement in its own worker and caches
    it (``capacity_curve``), so the report does not compute it: the catalog portal's sway starts at
    alpha = b / h = 0.3 / 1.5 = 0.2 and falls as the columns turn. The cone stage (3D friction
    model only) does not follow it."""
    from reports.stages import la_options, run_la
    from tests.conftest import ROOT

    path = ROOT / "scenes" / "catalog" / "portal-2d.json"
    data = json.loads(path.read_text())
    la = run_la(str(path), la_options(data))
    kin = la["capacity_curve"]
    assert kin["alpha"][0] == pytest.approx(0.2, rel=1e-6) and kin["alpha"][-1] < 0.5 * kin["alpha"][0]
    assert "capacity_curve" not in run_la(str(path), la_options(data), curve=False)
