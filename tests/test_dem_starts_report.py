"""The validation run's DEM starts (reports.dem_starts) and the contradiction count of the report
(reports.table.contradictions), on two blocks side by side (scenes.builders.side_by_side, mu = 0.5),
whose frictional collapse is 23/61 in closed form (derived in the builder's docstring; the
mechanism's displacement is derived in tests/test_dem_start.py)."""
import json
import math

import pandas as pd
import pytest

from limit.analysis import analyse
from limit.model.scene import load_scene
from reports import dem_starts, table
from scenes import builders as B
from tests.conftest import eccentric_slab_run, side_by_side_collapse_forces

CLOSED = B.side_by_side_alpha(mu=0.5)
MECHANISM = {"A": [0.5, 0.1, -1.0], "B": [0.6, 0.0, 0.0]}


@pytest.fixture(scope="module")
def scene_file(tmp_path_factory):
    d = B.side_by_side(dim=2, mu=0.5, name="sbs")
    path = tmp_path_factory.mktemp("dstart") / "sbs.json"
    path.write_text(json.dumps(d))
    return path


@pytest.fixture(scope="module")
def la(scene_file):
    return json.loads(json.dumps(analyse(load_scene(scene_file), method="nlp").data, default=float))


def _dem(alpha):
    return {"status": "collapsed", "alpha": alpha, "displacement": MECHANISM}


def test_an_engine_below_a_step2_that_stopped_high_is_resolved_by_its_state(scene_file, la):
    """Step 2's alpha is set to 0.41 (as if it had stopped above the minimum); YADE collapses at
    0.375: below it by 8.5 %. From YADE's state step 2 verifies 23/61 = 0.37705, which becomes the
    frictional alpha; YADE is then 0.5 % below it, inside the 1 % slack: the count goes from 1 to 0."""
    high = json.loads(json.dumps(la))
    high["nlp"]["alpha"] = 0.41
    results = {("sbs", "la"): high, ("sbs", "dem"): _dem(0.375)}
    starts = dem_starts.run([scene_file], results, progress=False)
    (entry,) = starts["sbs"]
    assert entry["adopted"] is True and entry["alpha"] == pytest.approx(CLOSED, rel=1e-9)
    assert entry["engine"] == "yade" and entry["fric_before"] == 0.41
    df = table.results_table([scene_file], results, with_dem=True, dem_start=starts)
    assert df["fric_alpha"].iloc[0] == pytest.approx(CLOSED) and df["fric_alpha_step2"].iloc[0] == 0.41
    assert len(table.contradictions(df, step2_only=True)) == 1 and table.contradictions(df) == []
    text = table.contradictions_markdown(df)
    assert "0 of 1 collapsed engine results (1 against step 2 before the DEM starts)" in text
    assert "sbs: step 2 from the yade collapse state verified 0.37705" in text


def test_an_engines_contact_forces_resolve_it_where_its_motion_does_not(scene_file, la):
    """As above, step 2 set to 0.41, and an engine result whose displacement moves nothing but
    whose last run holds the contact forces of the closed-form collapse state: the N iteration
    from them verifies 23/61, which becomes the frictional alpha."""
    high = json.loads(json.dumps(la))
    high["nlp"]["alpha"] = 0.41
    forces, _ = side_by_side_collapse_forces(load_scene(scene_file))
    dem = {**_dem(0.375), "displacement": {"A": [0.0, 0.0, 0.0]}, "runs": [{"eps": 2.5e-6, "held_forces": forces}]}
    starts = dem_starts.run([scene_file], {("sbs", "la"): high, ("sbs", "dem"): dem}, progress=False)
    (entry,) = starts["sbs"]
    assert entry["adopted"] is True and entry["alpha"] == pytest.approx(CLOSED, rel=1e-6) and entry["tau"] is None


def test_an_engine_below_the_true_minimum_stays_a_counted_contradiction(scene_file, la):
    """YADE at 0.30, 20 % below the closed form that step 2 found: its state verifies 23/61 again,
    nothing lower, so the contradiction stays and is listed with its gap."""
    results = {("sbs", "la"): la, ("sbs", "dem"): _dem(0.30)}
    starts = dem_starts.run([scene_file], results, progress=False)
    assert starts["sbs"][0]["adopted"] is False
    df = table.results_table([scene_file], results, with_dem=True, dem_start=starts)
    (c,) = table.contradictions(df)
    assert c[:2] == ("sbs", "YADE") and c[4] == pytest.approx(0.30 / CLOSED - 1)


def test_no_start_where_the_engines_are_inside_the_bracket(scene_file, la):
    results = {("sbs", "la"): la, ("sbs", "dem"): _dem(0.38), ("sbs", "lmgc"): {"status": "stable", "alpha": None}}
    assert dem_starts.run([scene_file], results, progress=False) == {}
    df = table.results_table([scene_file], results, with_dem=True, with_lmgc=True, dem_start={})
    assert table.contradictions(df) == [] and isinstance(df, pd.DataFrame)


@pytest.fixture(scope="module")
def slab(tmp_path_factory):
    """The eccentric slab (scenes.builders.eccentric_slab, e = 0.25 m, mu 0.6) as a file, its
    ``la`` and ``cone`` stages as the validation runs them (reports.stages), and the loaded scene."""
    from reports.stages import cone_options, la_options, run_cone, run_la

    d = B.eccentric_slab(e=0.25, mu=0.6, name="slab")
    path = tmp_path_factory.mktemp("pc") / "slab.json"
    path.write_text(json.dumps(d))
    la_res = json.loads(json.dumps(run_la(str(path), la_options(d), curve=False), default=float))
    cone = json.loads(json.dumps(run_cone(str(path), cone_options(d)), default=float))
    return path, la_res, cone, load_scene(path)


def test_a_3d_engine_below_the_papers_joints_is_judged_on_point_contacts_in_the_report(slab):
    """The slab pushed 0.25 m off its centre (mu 0.6): the cone stage's step 2 slides it at
    mu cos(pi/24) = 0.59487 (the paper's joints), while on four corner contacts a collapse state
    with equal normal forces lies at the closed form of
    :func:`scenes.builders.eccentric_slab_alpha`, 0.54417 (derived in its docstring). YADE at
    0.54 and LMGC90 at 0.50: both suspect low on the paper's joints. The validation's DEM starts
    find nothing lower there, so each entry tries point contacts; the lowest verified state there
    lies at or below the closed form. The table then judges YADE inside on point contacts and
    LMGC90 still suspect low against that point, and the contradiction count goes from 2 to 1."""
    path, la_res, cone, scene = slab
    corners = B.eccentric_slab_alpha(0.25, mu=0.6)
    assert cone["nlp"]["alpha"] == pytest.approx(0.6 * math.cos(math.pi / 24), rel=1e-5)
    results = {("slab", "la"): la_res, ("slab", "cone"): cone, ("slab", "dem"): eccentric_slab_run(scene, 0.54),
               ("slab", "lmgc"): eccentric_slab_run(scene, 0.50)}
    starts = dem_starts.run([path], results, progress=False)
    assert [e["engine"] for e in starts["slab"]] == ["yade", "lmgc90"]
    for e in starts["slab"]:
        assert e["adopted"] is False
        pc = e["point_contacts"]
        assert pc["alpha"] <= corners * (1 + 1e-6) and pc["alpha"] <= pc["lp_alpha"] * (1 + 1e-6)
    df = table.results_table([path], results, with_dem=True, with_lmgc=True, dem_start=starts)
    r = df.iloc[0]
    assert r["dem_bracket"] == "" and r["dem_bracket_model"].startswith("point contacts")
    assert r["lmgc_bracket"] == "suspect low" and r["pc_alpha"] <= corners * (1 + 1e-6)
    assert len(table.contradictions(df, step2_only=True)) == 2
    (c,) = table.contradictions(df)
    assert c[:2] == ("slab", "LMGC90 (point contacts)") and c[3] == pytest.approx(r["pc_alpha"])
    text = table.contradictions_markdown(df)
    assert "1 of 2 collapsed engine results (2 against step 2 before" in text
    assert "YADE and LMGC90 judged on point contacts" in text
