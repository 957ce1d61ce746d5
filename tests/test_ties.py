"""Tie rods: the scene's ``ties`` (limit/model/ties.py), tension-only members of capacity C (N)
between a point of a block and a point of another, in both steps, against closed forms derived
here. A 0.4 m wide, 1.0 m tall block (0.3 m deep in 3D; density 2000 kg/m^3, g = 9.81 m/s^2, a
2D scene 1 m thick) stands on a fixed base beside a fixed post; the live load is a horizontal
body force along +x."""
import json

import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.model.scene import load_scene
from scenes import builders as B

RHO_G = 2000.0 * 9.81


def _tied(dim, b=0.4, h=1.0, mu=0.9, side="left", height=None, capacity=1000.0, **extra):
    """The block, a fixed post 0.3 m to its left (or right), and a horizontal tie at ``height``
    (default the top) from the block's face to the post."""
    d = B.single_block(dim=dim, b=b, h=h, t=0.3 if dim == 3 else None, mu=mu)
    z = h if height is None else height
    x_blk, x_post, cx = (0.0, -0.3, -0.4) if side == "left" else (b, b + 0.3, b + 0.4)
    if dim == 2:
        post = B.box_block("post", [cx, 0.5 * h], [0.2, h], fixed=True)
        pa, pb = [x_blk, z], [x_post, z]
    else:
        post = B.box_block("post", [cx, 0.15, 0.5 * h], [0.2, 0.3, h], fixed=True)
        pa, pb = [x_blk, 0.15, z], [x_post, 0.15, z]
    d["blocks"].append(post)
    d["ties"] = [{"id": "rod", "from": {"block": "block", "point": pa}, "to": {"block": "post", "point": pb},
                  "capacity": capacity, **extra}]
    return d


def _weight(dim, b=0.4, h=1.0):
    return RHO_G * b * h * (0.3 if dim == 3 else 1.0)


@pytest.mark.parametrize("dim", [2, 3])
def test_a_tie_at_the_top_holds_back_overturning(dim):
    """Overturning about the far toe, the tie at the top of the near face stretching and yielding
    at C: moments about the toe, alpha W h/2 = W b/2 + C h, alpha = b/h + 2 C / W. 2D: W = 7,848 N,
    alpha = 0.4 + 0.254842; 3D: W = 2,354.4 N, alpha = 0.4 + 0.849473. Sliding would need mu + C / W
    >= 1.03 (0.9 and the tie), so rocking governs, and step 2 keeps the LP's point."""
    W = _weight(dim)
    res = analyse(load_scene(_tied(dim, prestress=300.0)), method="nlp").data
    want = 0.4 + 2 * 1000.0 / W
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)
    (tie,) = res["lp"]["ties"]
    assert tie["id"] == "rod" and tie["state"] == "yields" and tie["tension"] == pytest.approx(1000.0, rel=1e-6)
    assert tie["prestress"] == 300.0


@pytest.mark.parametrize("dim", [2, 3])
def test_a_tie_holds_back_sliding_by_its_capacity(dim):
    """A squat block (1.0 x 0.5 m, mu 0.3) slides: alpha W = mu W + C, alpha = mu + C / W with the
    tie at mid-height (horizontal: the slide stretches it by the slip; the LP's dilatant lift does
    not change its length to first order). 2D: W = 9,810 N; 3D: 3,924 N."""
    W = _weight(dim, 1.0, 0.5)
    res = analyse(load_scene(_tied(dim, b=1.0, h=0.5, mu=0.3, height=0.25)), method="nlp").data
    want = 0.3 + 1000.0 / W
    assert res["lp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["alpha"] == pytest.approx(want, rel=1e-6)
    assert res["nlp"]["ties"][0]["state"] == "yields"


def test_a_tie_on_the_far_side_goes_slack():
    """The tie to a post on the side the block moves towards shortens as it overturns: slack, no
    force, and the block's own b / h = 0.4."""
    res = analyse(load_scene(_tied(2, side="right")), method="nlp").data
    assert res["lp"]["alpha"] == pytest.approx(0.4, rel=1e-6)
    assert res["lp"]["ties"][0]["state"] == "slack"
    assert abs(res["lp"]["ties"][0]["tension"]) < 1e-6 * 1000.0


def test_tie_points_follow_the_scenes_units():
    """The same scene in millimetres: the tie's points scale with the blocks, so alpha is the same."""
    d = _tied(2)
    mm = json.loads(json.dumps(d))
    mm["units"] = "mm"
    for b in mm["blocks"]:
        b["box"]["center"] = [1000 * c for c in b["box"]["center"]]
        b["box"]["size"] = [1000 * c for c in b["box"]["size"]]
    for side in ("from", "to"):
        mm["ties"][0][side]["point"] = [1000 * c for c in mm["ties"][0][side]["point"]]
    assert analyse(load_scene(mm), method="lp").data["lp"]["alpha"] == pytest.approx(0.4 + 2000.0 / _weight(2), rel=1e-6)


@pytest.mark.parametrize("change, match", [
    (lambda t: t["from"].update(point=[0.0, 1.6]), r"ties\[0\]\.from\.point: lies outside block 'block'"),
    (lambda t: t["to"].update(block="nope"), r"ties\[0\]\.to\.block: unknown block id 'nope'"),
    (lambda t: t["to"].update(block="block", point=[0.2, 0.5]), r"ties\[0\]: both ends are in block 'block'"),
    (lambda t: t["from"].update(block="base", point=[0.0, -0.1]), r"ties\[0\]: both ends are fixed blocks"),
    (lambda t: t.update(capacity=-5.0), r"ties\[0\]\.capacity"),
    (lambda t: t.update(prestress=2000.0), r"ties\[0\]\.prestress: 2000 N is above its capacity 1000 N"),
    (lambda t: t["from"].update(point=[0.0]), r"ties\[0\]\.from\.point"),
])
def test_tie_mistakes_are_named(change, match):
    d = _tied(2)
    change(d["ties"][0])
    with pytest.raises(SceneError, match=match):
        load_scene(d)


def test_lmgc90_and_yades_polyhedra_skip_a_tied_scene_with_the_reason():
    from dem_validation.api import run_loaded
    from dem_validation.lmgc import run_loaded_lmgc90

    s = load_scene(_tied(2))
    for out in (run_loaded(s, {}, contact="polyhedra"), run_loaded_lmgc90(s, {})):
        assert out["status"] == "skipped" and "tie" in out["reason"]


@pytest.mark.yade
@pytest.mark.parametrize("dim", [2, 3])
def test_yade_carries_the_tie_to_the_closed_form(dim):
    """YADE's vertex model with the tie as a spring capped at its capacity (dem_validation/
    engines/yade/yade_model.py, ``apply_ties``) collapses within 2 % of b/h + 2 C / W (first test), and the
    block without its tie within 2 % of b/h = 0.4."""
    from dem_validation.api import run_scene

    W = _weight(dim)
    tied = run_scene(load_scene(_tied(dim)))
    assert tied["status"] == "collapsed"
    assert tied["alpha"] == pytest.approx(0.4 + 2 * 1000.0 / W, rel=0.02)
    bare = _tied(dim)
    bare.pop("ties")
    free = run_scene(load_scene(bare))
    assert free["status"] == "collapsed" and free["alpha"] == pytest.approx(0.4, rel=0.02)


def test_the_capacity_curve_is_refused_for_a_tied_scene():
    """The finite-displacement curve counts the loads' work alone: with a tie it would start from
    the untied block's 0.4, so it is refused, saying why."""
    from limit.verdict.capacity_curve import follow

    s = load_scene(_tied(2))
    lp = analyse(s, method="lp").data["lp"]
    with pytest.raises(ValueError, match="tie rods"):
        follow(s, lp["mechanism"], lp["alpha"])
