"""Compound blocks in the DEM engines: YADE clumps a compound block's parts into one rigid body
(tests/test_compound.py derives the closed forms); LMGC90's wheel builds one convex polyhedron per
body, so a scene with a compound block is skipped with the reason. The tolerance after YADE's
extrapolation to rigid contacts is tests/test_dem_yade.py's 2 % on rocking."""
import pytest

from dem_validation import run_scene
from tests.test_compound import compound_springer_arch, compound_springer_reference, l_block_2d, l_block_3d

RTOL = 0.02


@pytest.mark.yade
@pytest.mark.parametrize("builder", [l_block_2d, l_block_3d])
def test_yade_l_block_overturns_at_the_closed_form(builder):
    """alpha = x_c / y_c = 1 (tests/test_compound.py), toppling towards -x."""
    dem = run_scene(builder(-1.0), timeout_s=600)
    assert dem["status"] == "collapsed", dem.get("reason")
    assert dem["alpha"] == pytest.approx(1.0, rel=RTOL)
    assert dem["displacement"]["L"][0] < 0


@pytest.mark.yade
def test_yade_arch_with_compound_springers_at_the_four_hinge_value():
    dem = run_scene(compound_springer_arch(), timeout_s=600)
    assert dem["status"] == "collapsed", dem.get("reason")
    assert dem["alpha"] == pytest.approx(compound_springer_reference(), rel=RTOL)


@pytest.mark.lmgc90
def test_lmgc90_skips_a_compound_block_with_the_reason():
    dem = run_scene(l_block_2d(), engine="lmgc90", timeout_s=300)
    assert dem["status"] == "skipped", dem
    assert "block L is compound" in dem["reason"] and "one convex polyhedron per body" in dem["reason"]


def test_the_polyhedra_contact_model_refuses_a_compound_block():
    dem = run_scene(l_block_2d(), contact="polyhedra", timeout_s=60)
    assert dem["status"] == "failed" and "block 'L' is compound" in dem["reason"]
