"""Input mistakes that once passed silently or ended in an internal error, each rejected (exit 2)
with one line naming the load, entry or key, or answered naming what is at fault (issue 42,
item 5): a point force outside its block, a live load that does no work, a friction override
for blocks that do not touch, the ``units`` key, the gap of a block that touches nothing, and
the mechanism of a dead load that cannot be carried."""
import copy
import json
from pathlib import Path

import pytest

from limit.analysis import analyse
from limit.cli import main
from limit.errors import SceneError
from limit.model.scene import load_scene
from scenes import builders as B
from tests.test_scene_errors import GOOD2, GOOD3, check_rejected, edited

ROCKING = json.loads((Path(__file__).parents[1] / "scenes/catalog/block-rocking-2d.json").read_text())
FOOT = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.2], [0.0, 0.2]]
LEG = [[0.0, 0.2], [0.2, 0.2], [0.2, 1.0], [0.0, 1.0]]


def l_block(point, units=None, k=1.0) -> dict:
    """The L-shaped compound block of tests/test_compound.py with a point force at ``point``
    (coordinates in metres, written times ``k`` in the file's ``units``)."""
    s = lambda v: [x * k for x in v]  # noqa: E731
    d = {"format": "blockscene/1", "dim": 2, "friction": 3.0,
         "blocks": [{"id": "base", "box": {"center": s([0.5, -0.1]), "size": s([3.0, 0.2])}, "fixed": True},
                    {"id": "L", "parts": [{"vertices": [s(v) for v in FOOT]}, {"vertices": [s(v) for v in LEG]}]}],
         "loads": {"live": [{"type": "point_force", "block": "L", "force": [-1000.0, 0.0], "point": s(point)}]}}
    if units:
        d["units"] = units
    return d


# ----------------------------------------------------------------------------- point forces

def test_point_force_outside_its_block_names_the_load_the_block_and_the_distance(capsys, write_scene):
    d = edited(GOOD2, lambda d: d["loads"].update(
        live=[{"type": "point_force", "block": "c1-1", "force": [1, 0], "point": [0.4, 2.0]}]))
    check_rejected(capsys, write_scene(d), "loads.live[0].point", "outside block 'c1-1'", "1.65 m from it")


def test_point_force_on_the_surface_or_within_the_tolerance_is_accepted(write_scene):
    top = 0.35  # c1-1's top face
    for y in (top, top + 1e-7):
        d = edited(GOOD2, lambda d: d["loads"].update(
            live=[{"type": "point_force", "block": "c1-1", "force": [1, 0], "point": [0.4, y]}]))
        load_scene(d)


def test_point_force_in_a_compound_block_must_lie_in_one_of_its_parts():
    """(0.1, 0.6) is in the leg; (0.6, 0.6), in the notch of the L, is inside the hull of the
    block but 0.4 m from both parts."""
    load_scene(l_block([0.1, 0.6]))
    with pytest.raises(SceneError, match=r"loads\.live\[0\]\.point: \[0\.6, 0\.6\] lies outside block 'L', 0\.4 m"):
        load_scene(l_block([0.6, 0.6]))


# ----------------------------------------------------------------------------- live loads doing no work

@pytest.mark.parametrize("live,frag", [
    ([{"type": "body_force", "direction": [0, 0]}], "loads.live[0] (body_force) has a zero direction"),
    ([{"type": "point_force", "block": "c1-1", "force": [0, 0]}], "loads.live[0] (point_force) has a zero force"),
    ([{"type": "body_force", "direction": [1, 0], "blocks": ["base"]}],
     "loads.live[0] (body_force) acts on fixed blocks only ('base')"),
    ([{"type": "body_force", "direction": [1, 0]}, {"type": "body_force", "direction": [-1, 0]}],
     "loads.live[1] (body_force) is cancelled by the others"),
    ([], "loads.live: no live load"),
])
def test_a_live_load_that_does_no_work_is_rejected_naming_it(capsys, write_scene, live, frag):
    """Once "failed: ZeroDivisionError" with exit status 1 (step 2 from the unbounded LP); found
    again by tests/test_fuzz.py's load mutations."""
    p = write_scene(edited(GOOD2, lambda d: d["loads"].update(live=live)))
    check_rejected(capsys, p, frag)
    assert main(["solve", str(p)]) == 2
    assert frag in capsys.readouterr().err


def test_a_live_load_on_blocked_dofs_only_is_rejected():
    d = copy.deepcopy(ROCKING)
    d["blocks"][1]["blocked"] = ["x"]
    with pytest.raises(SceneError, match=r"loads\.live\[0\] \(body_force\) acts only along dofs its blocks have 'blocked'"):
        load_scene(d)


# ----------------------------------------------------------------------------- friction overrides

@pytest.mark.parametrize("extra,pair,frag", [
    ([{"id": "far", "box": {"center": [3.0, 0.0875], "size": [0.4, 0.175]}}], ["c0-0", "far"],
     "'c0-0' and 'far' do not touch (2.4 m apart"),
    ([{"id": "foot2", "box": {"center": [3.0, -0.1], "size": [1.0, 0.2]}, "fixed": True}], ["base", "foot2"],
     "'base' and 'foot2' are both fixed"),
    ([{"id": "corner", "box": {"center": [1.0, 0.0875], "size": [0.4, 0.175]}}], ["c1-2", "corner"],
     "'c1-2' and 'corner' meet only at a corner or an edge"),
])
def test_a_friction_override_for_blocks_without_an_interface_is_rejected_naming_it(capsys, write_scene, extra, pair,
                                                                                   frag):
    d = copy.deepcopy(GOOD2)
    d["blocks"] += extra
    d["interfaces"] = {"friction": [{"blocks": ["c0-0", "c0-1"], "mu": 0.3}, {"blocks": pair, "mu": 0.4}]}
    check_rejected(capsys, write_scene(d), "interfaces.friction[1].blocks", frag)
    with pytest.raises(SceneError, match=r"interfaces\.friction\[1\]"):
        analyse(load_scene(d), method="lp")


def test_the_dem_command_rejects_a_friction_override_for_blocks_without_an_interface(capsys, write_scene):
    """Before any engine starts: exit 2 and the entry named, as limit solve does."""
    import dem_validation.cli

    d = copy.deepcopy(GOOD2)
    d["blocks"].append({"id": "far", "box": {"center": [3.0, 0.0875], "size": [0.4, 0.175]}})
    d["interfaces"] = {"friction": [{"blocks": ["c0-0", "far"], "mu": 0.4}]}
    assert dem_validation.cli.main(["run", str(write_scene(d)), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: interfaces.friction[0].blocks: 'c0-0' and 'far' do not touch")


def test_a_friction_override_for_touching_blocks_is_accepted(write_scene):
    d = edited(GOOD2, lambda d: d.update(interfaces={"friction": [{"blocks": ["c1-1", "c0-1"], "mu": 0.3}]}))
    assert main(["info", str(write_scene(d))]) == 0


# ----------------------------------------------------------------------------- units

@pytest.mark.parametrize("units,k", [("mm", 1000.0), ("cm", 100.0)])
def test_units_convert_every_length_to_metres(units, k):
    """The rocking block (alpha = b/h = 0.3) and the L block written in mm and cm: the same
    alpha, mass, bounding box (m) and tolerance."""
    d = copy.deepcopy(ROCKING)
    d["units"] = units
    for b in d["blocks"]:
        b["box"] = {key: [x * k for x in v] for key, v in b["box"].items()}
    d["tolerance"] = 1e-6 * k
    s, ref = load_scene(d, strict=True), load_scene(ROCKING)
    assert s.total_mass == pytest.approx(ref.total_mass, rel=1e-12)
    assert s.bbox() == pytest.approx(ref.bbox(), rel=1e-12)
    assert s.tolerance == pytest.approx(1e-6, rel=1e-12)
    res = analyse(s, method="lp").data
    assert res["lp"]["alpha"] == pytest.approx(analyse(ref, method="lp").data["lp"]["alpha"], rel=1e-9)
    assert res["units"]["length"] == "m"
    big = load_scene(l_block([0.1, 0.6], units=units, k=k))
    assert big.blocks[1].mass == pytest.approx(load_scene(l_block([0.1, 0.6])).blocks[1].mass, rel=1e-12)
    with pytest.raises(SceneError, match="outside block 'L', 0.4 m"):
        load_scene(l_block([0.6, 0.6], units=units, k=k))


def test_units_scale_the_2d_thickness():
    d = copy.deepcopy(ROCKING)
    d.update(units="mm", thickness=500.0)
    for b in d["blocks"]:
        b["box"] = {key: [x * 1000 for x in v] for key, v in b["box"].items()}
    s = load_scene(d)
    assert s.thickness == 0.5
    assert s.total_mass == pytest.approx(0.5 * load_scene(ROCKING).total_mass, rel=1e-12)


def test_units_is_a_known_key_and_a_bad_value_is_rejected(capsys, write_scene):
    load_scene(edited(ROCKING, lambda d: d.update(units="m")), strict=True)
    check_rejected(capsys, write_scene(edited(GOOD2, lambda d: d.update(units="inch"))), "units", "\"inch\"")


# ----------------------------------------------------------------------------- a block that touches nothing

def test_touches_no_other_block_names_the_gap_and_the_tolerance_key_that_closes_it():
    d = copy.deepcopy(ROCKING)
    d["blocks"][1]["box"]["center"][1] += 0.002
    with pytest.raises(SceneError) as exc:
        analyse(load_scene(d), method="lp")
    msg = str(exc.value)
    assert "block 'block' touches no other block" in msg
    assert "the nearest block, 'base', is 0.002 m away" in msg and '"tolerance": 0.00202' in msg
    d["tolerance"] = 0.00202  # what the message says closes the gap
    res = analyse(load_scene(d), method="lp").data
    assert res["n_interfaces"] == 1 and res["lp"]["alpha"] == pytest.approx(0.3, rel=1e-2)


def test_a_loose_block_among_others_is_named_with_its_gap():
    d = copy.deepcopy(GOOD2)
    d["blocks"].append({"id": "float", "box": {"center": [0.4, 0.5375], "size": [0.2, 0.175]}})
    res = analyse(load_scene(d), method="lp").data
    assert res["lp"]["status"] == "infeasible"
    reason = res["lp"]["reason"]
    assert "float" in reason and "'c1-1', is 0.1 m away" in reason and '"tolerance"' in reason


# ----------------------------------------------------------------------------- dead-load collapse

def _overhang() -> dict:
    """The 2 x 2 wall with its top right block pushed 0.15 m over the edge of the course below
    (centroid beyond the support): it tips off under its own weight."""
    return edited(GOOD2, lambda d: d["blocks"][5]["box"]["center"].__setitem__(0, 0.85))


def test_a_dead_load_collapse_names_the_blocks_and_joints_of_its_mechanism():
    res = analyse(load_scene(_overhang()), method="lp").data
    lp = res["lp"]
    assert lp["status"] == "infeasible"
    dead = lp["dead_load_mechanism"]
    assert dead["blocks"] == ["c1-2"]
    assert [j["blocks"] for j in dead["joints"]] == [["c0-1", "c1-2"]] and "rock" in dead["joints"][0]["modes"]
    assert "dead-load mechanism: block 'c1-2' moves; joints c0-1|c1-2 (rock" in lp["reason"]
    u = dead["mechanism"]["c1-2"]
    assert u[2] < 0  # it turns clockwise, off the right edge


def test_a_dead_load_collapse_in_3d_names_its_mechanism():
    d = edited(GOOD3, lambda d: d["blocks"][-1]["box"]["center"].__setitem__(0, 0.85))
    lp = analyse(load_scene(d), method="lp").data["lp"]
    assert lp["status"] == "infeasible" and lp["dead_load_mechanism"]["blocks"] == [d["blocks"][-1]["id"]]


def test_solve_draws_the_dead_load_mechanism(tmp_path, write_scene, capsys):
    png = tmp_path / "m.png"
    assert main(["solve", str(write_scene(_overhang())), "--method", "lp", "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "dead-load mechanism: block 'c1-2'" in out
    assert png.stat().st_size > 1000 and png.read_bytes()[:4] == b"\x89PNG"


def test_the_dead_load_figure_is_titled_as_the_dead_load_collapse():
    """The figure of an infeasible LP draws one panel, the dead-load mechanism, under its own label."""
    from reports.plots import LABELS, _panels

    panels = _panels(analyse(load_scene(_overhang()), method="lp").data, None)
    assert [p[0] for p in panels] == ["dead"] and "dead load" in LABELS["dead"]
    assert [b for b, u in panels[0][1].items() if max(map(abs, u)) > 1e-9] == ["c1-2"]


def test_solve_draws_the_collapse_mechanism(tmp_path, write_scene, capsys):
    png = tmp_path / "m.png"
    assert main(["solve", str(write_scene(ROCKING)), "--method", "lp", "--plot", str(png)]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_builders_scenes_still_carry_their_dead_load():
    assert analyse(load_scene(B.running_bond_wall(2, 2, dim=2)), method="lp").data["lp"]["status"] == "optimal"


def test_the_direction_sweep_reads_a_direction_that_does_no_work_as_no_mechanism():
    """A block held in y (a roller): the live load turned onto y does no work there, which the
    sweep records as "unbounded" (no mechanism) instead of failing."""
    from limit.direction_sweep import sweep

    data = B.single_block(3, 0.3, 1.0, t=0.3, mu=0.8)
    data["blocks"][1]["blocked"] = ["y", "rx", "rz"]
    out = sweep(data, 90.0, jobs=1, frictional=False)
    status = dict(zip(out["theta"], out["status"]))
    assert status[90.0] == "unbounded" and status[270.0] == "unbounded" and status[0.0] == "optimal"


def test_solve_plots_into_a_folder_with_the_interactive_view(tmp_path, write_scene, capsys):
    """--plot DIR writes the PNG and the interactive page, for the dead-load mechanism too (one
    figure, of the block that falls)."""
    out = tmp_path / "figs"
    assert main(["solve", str(write_scene(_overhang())), "--method", "lp", "--plot", str(out) + "/"]) == 0
    pages = list(out.glob("*-mechanism.html"))
    assert len(pages) == 1 and (out / pages[0].name.replace(".html", ".png")).exists()
    page = pages[0].read_text()
    assert page.count('class="plotly-graph-div"') == 1 and "collapse under the dead load alone" in page
