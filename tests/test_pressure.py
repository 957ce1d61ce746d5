"""Pressure loads (limit/model/pressure.py): uniform and linear with height on the faces that
face one direction, against closed forms derived here. A 0.4 m wide, 1.0 m tall block (0.3 m
deep in 3D; density 2000 kg/m^3, g = 9.81 m/s^2, a 2D scene 1 m thick: W = 7,848 N in 2D, 2,354.4 N
in 3D) on a fixed base, mu 0.9; the pressure acts on its left face (outward normal -x), of area
h t (t = 1 m in 2D, 0.3 m in 3D)."""
import pytest

from limit.analysis import analyse
from limit.errors import SceneError
from limit.model.scene import load_scene
from scenes import builders as B

GAMMA = 9810.0  # water, Pa/m


def _block(dim, **pressure):
    d = B.single_block(dim=dim, b=0.4, h=1.0, t=0.3 if dim == 3 else None, mu=0.9)
    face = [-1.0, 0.0] if dim == 2 else [-1.0, 0.0, 0.0]
    d["loads"]["live"] = [{"type": "pressure", "blocks": ["block"], "face": face, **pressure}]
    return d


def _t(dim):
    return 1.0 if dim == 2 else 0.3


def _W(dim):
    return 2000.0 * 9.81 * 0.4 * 1.0 * _t(dim)


def _alpha(d, method="lp"):
    return analyse(load_scene(d), method=method).data["lp"]["alpha"]


@pytest.mark.parametrize("dim", [2, 3])
def test_a_uniform_pressure_overturns_the_block(dim):
    """p = 1,000 Pa: a resultant p h t at mid-height. Overturning about the toe: alpha p h t h/2 =
    W b/2, alpha = W b / (p h^2 t) = 3.1392 either way; sliding needs 0.9 W / (p h t), more."""
    assert _alpha(_block(dim, value=1000.0)) == pytest.approx(_W(dim) * 0.4 / (1000.0 * _t(dim)), rel=1e-9)


@pytest.mark.parametrize("dim", [2, 3])
def test_water_to_the_top_overturns_it_at_a_third_of_the_height(dim):
    """p = gamma (h - z): a resultant gamma h^2 t / 2 at h/3. Overturning: alpha gamma h^3 t / 6 = W b / 2,
    alpha = 3 W b / (gamma h^3 t) = 0.96; sliding needs 0.9 x 2 W / (gamma h^2 t) = 1.44."""
    assert _alpha(_block(dim, value=0.0, gradient=GAMMA, level=1.0)) == pytest.approx(
        3 * _W(dim) * 0.4 / (GAMMA * _t(dim)), rel=1e-9)


@pytest.mark.parametrize("dim", [2, 3])
def test_water_to_half_height_is_cut_at_its_surface(dim):
    """Water to z = 0.5 m: no pressure above it, a resultant gamma (h/2)^2 t / 2 at h/6. Sliding,
    alpha = 0.9 W / (gamma t / 8) = 5.76, comes before overturning, 3 W b / (gamma (h/2)^3 t) = 7.68."""
    assert _alpha(_block(dim, value=0.0, gradient=GAMMA, level=0.5)) == pytest.approx(
        0.9 * _W(dim) * 8 / (GAMMA * _t(dim)), rel=1e-9)


def test_a_pressure_as_dead_load_and_in_millimetres():
    """Backfill p = 1,000 Pa on the left face as a dead load, the live load a body force: moments
    about the toe, alpha W h/2 + p h t h/2 = W b/2, alpha = (W b - p h^2 t) / (W h) = 0.272579 (2D).
    The same scene in millimetres (the level scales, the pressure and its gradient do not) gives
    the hydrostatic case's 0.96."""
    d = B.single_block(dim=2, b=0.4, h=1.0, mu=0.9)
    d["loads"]["dead"].append({"type": "pressure", "blocks": ["block"], "face": [-1.0, 0.0], "value": 1000.0})
    W = _W(2)
    assert _alpha(d) == pytest.approx((W * 0.4 - 1000.0) / W, rel=1e-9)
    mm = _block(2, value=0.0, gradient=GAMMA, level=1000.0)
    mm["units"] = "mm"
    for b in mm["blocks"]:
        b["box"] = {k: [1000 * x for x in v] for k, v in b["box"].items()}
    assert _alpha(mm) == pytest.approx(3 * W * 0.4 / GAMMA, rel=1e-9)


def test_a_pressure_on_no_face_is_rejected_naming_it():
    with pytest.raises(SceneError, match=r"loads\.live\[0\] \(pressure\) loads no face"):
        load_scene(_block(2, value=1000.0) | {"loads": {"dead": [{"type": "self_weight"}], "live": [
            {"type": "pressure", "blocks": ["block"], "face": [0.0, -1.0], "value": -5.0}]}})
    with pytest.raises(SceneError, match=r"loads\.live\[0\]\.face"):
        load_scene(_block(2, value=1000.0) | {"loads": {"live": [
            {"type": "pressure", "blocks": ["block"], "face": [0.0, 0.0], "value": 5.0}]}})


@pytest.mark.yade
@pytest.mark.lmgc90
def test_both_engines_carry_the_water_pressure_to_the_closed_form():
    """The pressure enters the DEM as each block's generalised force, like every load: YADE and
    LMGC90 collapse the catalog's block-water-2d within 2 % of 3 W b / (gamma h^3 t) = 0.96."""
    from dem_validation.api import run_scene
    from tests.conftest import ROOT

    s = load_scene(ROOT / "scenes" / "catalog" / "block-water-2d.json")
    for engine in ("yade", "lmgc90"):
        out = run_scene(s, engine=engine)
        assert out["status"] == "collapsed" and out["alpha"] == pytest.approx(0.96, rel=0.02), engine
