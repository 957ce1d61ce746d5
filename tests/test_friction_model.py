"""The 3D friction model a scene gets: its own ``interfaces.sliding_faces``, else 24
inscribed faces (the default for a user's scene), and the options override both.

Closed forms, a squat block 1 x 1 x 0.5 (mu 0.4) sliding under a horizontal load at angle
theta to x (rocking needs far more): with K faces d_j at angles 2 pi j / K and capacities
c mu N, alpha = c mu / max_j cos(theta - theta_j):
  * the paper's 4 circumscribed faces (c = 1): mu / max(|cos|, |sin|), mu sqrt 2 at 45 deg;
  * 24 inscribed faces (c = cos(pi/24)): mu cos(pi/24) along a face normal (0, 15, 30, 45
    deg), mu exactly halfway between two (7.5, 22.5 deg).
Coulomb's circular cone gives mu in every direction (both dynamic engines: 0.400-0.401).
"""
import math

import pytest

from limit.analysis import analyse
from limit.model.assemble import Options
from limit.model.scene import load_scene
from scenes import builders as B

MU = 0.4


def squat(deg, sliding_faces):
    d = B.single_block(dim=3, b=1.0, h=0.5, t=1.0, mu=MU, name="squat", sliding_faces=sliding_faces)
    th = math.radians(deg)
    d["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    return d


@pytest.mark.parametrize("deg", [0.0, 22.5, 45.0])
def test_a_users_scene_gets_24_inscribed_faces(deg):
    res = analyse(load_scene(squat(deg, None)), method="lp").data["lp"]
    assert res["model"]["n_slide"] == 24 and res["model"]["slide_fit"] == "inscribed"
    c = math.cos(math.pi / 24)
    want = c * MU / max(math.cos(math.radians(deg) - 2 * math.pi * j / 24) for j in range(24))
    assert res["alpha"] == pytest.approx(want, rel=1e-6)
    assert abs(res["alpha"] / MU - 1) <= 1 - c + 1e-9  # within 0.86 % of the cone, never above it


@pytest.mark.parametrize("deg", [0.0, 22.5, 45.0])
def test_a_scene_declaring_the_papers_faces_keeps_them(deg):
    res = analyse(load_scene(squat(deg, 4)), method="lp").data["lp"]
    th = math.radians(deg)
    assert res["model"]["n_slide"] == 4 and res["model"]["slide_fit"] == "circumscribed"
    assert res["alpha"] == pytest.approx(MU / max(abs(math.cos(th)), abs(math.sin(th))), rel=1e-6)


def test_options_override_the_scene():
    res = analyse(load_scene(squat(45.0, 4)), method="lp", options=Options(n_slide=24)).data["lp"]
    assert res["model"]["n_slide"] == 24 and res["alpha"] == pytest.approx(MU * math.cos(math.pi / 24), rel=1e-6)


def test_the_catalogs_3d_scenes_declare_the_papers_model():
    import json

    from scenes.catalog import catalog_files

    for f in catalog_files():
        d = json.loads(f.read_text())
        if d["dim"] == 3:
            assert d["interfaces"]["sliding_faces"] == 4, f.name
