"""The spectrum's parameters from the site (limit/model/site_spectrum.py, NTC 2018 3.2.3.2.1)
against hand calculations, and the demand built from a scene's ``demand`` or ``limit check``.

Hand calculations, F0 = 2.5 and Tc* = 0.30 s throughout (TC = CC Tc* = c Tc*^(1 - p) with CC = c
Tc*^-p of Table 3.2.IV; TB = TC / 3; TD = 4 ag/g + 1.6):

=====  ===========================================  ===========================================  ===================
soil   SS at ag = 0.05 g (F0 ag/g = 0.125)           SS at ag = 0.25 g (F0 ag/g = 0.625)          TC (s), both ag
=====  ===========================================  ===========================================  ===================
A      1.00                                         1.00                                         0.30
B      1.40 - 0.40 x 0.125 = 1.35 -> clipped 1.20    1.40 - 0.40 x 0.625 = 1.15                   1.10 x 0.3^0.80 = 0.41985
C      1.70 - 0.60 x 0.125 = 1.625 -> clipped 1.50   1.70 - 0.60 x 0.625 = 1.325                  1.05 x 0.3^0.67 = 0.46866
D      2.40 - 1.50 x 0.125 = 2.2125 -> clipped 1.80  2.40 - 1.50 x 0.625 = 1.4625                 1.25 x 0.3^0.50 = 0.68465
E      2.00 - 1.10 x 0.125 = 1.8625 -> clipped 1.60  2.00 - 1.10 x 0.625 = 1.3125                 1.15 x 0.3^0.60 = 0.55843
=====  ===========================================  ===========================================  ===================

TD = 4 x 0.05 + 1.6 = 1.8 s and 4 x 0.25 + 1.6 = 2.6 s. At ag = 0.40 g (F0 ag/g = 1.0) soil D
meets its lower clip: 2.40 - 1.50 = 0.90. Topography T2 half way up the slope: ST = 1 + (1.2 - 1)
x 0.5 = 1.1; T4 at the crest 1.4.
"""
import json
import subprocess
import sys

import pytest

from limit.errors import SceneError, SceneWarning
from limit.model.scene import load_scene
from limit.model.seismic_demand import from_mapping
from limit.model.site_spectrum import site_parameters

HAND = {  # soil: (SS at 0.05 g, SS at 0.25 g, TC s)
    "A": (1.00, 1.00, 0.30),
    "B": (1.20, 1.15, 0.41985),
    "C": (1.50, 1.325, 0.46866),
    "D": (1.80, 1.4625, 0.68465),
    "E": (1.60, 1.3125, 0.55843),
}


@pytest.mark.parametrize("soil", sorted(HAND))
@pytest.mark.parametrize("ag,col,TD", [(0.05, 0, 1.8), (0.25, 1, 2.6)])
def test_soil_categories_against_hand_calculations(soil, ag, col, TD):
    p = site_parameters(ag, 2.5, 0.30, soil)
    assert p["SS"] == pytest.approx(HAND[soil][col], abs=1e-12)
    assert p["S"] == pytest.approx(HAND[soil][col], abs=1e-12)  # T1: ST = 1
    assert p["TC"] == pytest.approx(HAND[soil][2], abs=5e-6)
    assert p["TB"] == pytest.approx(HAND[soil][2] / 3, abs=5e-6)
    assert p["TD"] == pytest.approx(TD, abs=1e-12)


def test_lower_clip_and_topography():
    assert site_parameters(0.40, 2.5, 0.30, "D")["SS"] == pytest.approx(0.90, abs=1e-12)
    p = site_parameters(0.25, 2.5, 0.30, "C", "T2", 0.5)
    assert p["ST"] == pytest.approx(1.1) and p["S"] == pytest.approx(1.325 * 1.1)
    assert site_parameters(0.25, 2.5, 0.30, "A", "T4")["ST"] == pytest.approx(1.4)


@pytest.mark.parametrize("kw,key", [({"soil": "F"}, "demand.soil"), ({"topography": "T5"}, "demand.topography"),
                                    ({"topography_ratio": 1.5}, "demand.topography_ratio"),
                                    ({"Tc_star": 0.0}, "demand.Tc_star")])
def test_bad_site_values_name_their_key(kw, key):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        site_parameters(**{"ag_g": 0.25, "F0": 2.5, "Tc_star": 0.3, **kw})


def test_demand_from_the_site_records_derived_and_overridden_values():
    d = from_mapping({"ag_g": 0.25, "F0": 2.5, "Tc_star": 0.30, "soil": "C", "TD": 2.0})
    assert d.S == pytest.approx(1.325) and d.TC == pytest.approx(0.46866, abs=5e-6)
    assert d.TB == pytest.approx(0.46866 / 3, abs=5e-6)
    assert d.TD == 2.0  # the explicit value overrides the code's 2.6 s, and the record says so
    assert d.site["derived"]["TD"] == pytest.approx(2.6) and d.site["overridden"] == {"TD": 2.0}
    assert d.site["soil"] == "C" and d.site["CC"] == pytest.approx(1.05 * 0.3 ** -0.33)
    with pytest.raises(ValueError, match=r"demand\.F0"):
        from_mapping({"ag_g": 0.25, "Tc_star": 0.3, "soil": "B"})
    with pytest.raises(ValueError, match=r"demand\.Tc_star"):
        from_mapping({"ag_g": 0.25, "F0": 2.5, "soil": "B"})
    plain = from_mapping({"ag_g": 0.25})
    assert plain.site is None and (plain.S, plain.TC, plain.TD) == (1.0, 0.5, 2.0)


def _scene_with(demand: dict) -> dict:
    from scenes import builders as B
    sc = B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)
    sc["demand"] = demand
    return sc


def test_an_unknown_demand_key_is_warned_and_ignored_never_an_internal_error():
    """A key that is not a demand's ("site_class") is a warning naming it, and the demand is
    built without it; under --strict it is a rejection."""
    with pytest.warns(SceneWarning, match="site_class"):
        sc = load_scene(_scene_with({"ag_g": 0.2, "site_class": "B"}))
    assert sc.demand.ag_g == 0.2
    with pytest.raises(SceneError, match="site_class"):
        load_scene(_scene_with({"ag_g": 0.2, "site_class": "B"}), strict=True)
    sc = load_scene(_scene_with({"ag_g": 0.25, "F0": 2.5, "Tc_star": 0.3, "soil": "D"}))
    assert sc.demand.S == pytest.approx(1.4625) and sc.demand.TC == pytest.approx(0.68465, abs=5e-6)


@pytest.mark.slow  # about 4 s: limit check end to end in subprocesses
def test_limit_check_derives_the_spectrum_from_the_site(tmp_path):
    """``limit check --ag 0.25 --F0 2.5 --Tc-star 0.3 --soil B``: the linear check's demand is
    ag S / q = 0.25 x 9.81 x 1.15 / 2 = 1.41019 m/s^2 (S = SS = 1.15 above), and the JSON's
    demand records the derived TC."""
    from scenes import builders as B
    p = tmp_path / "block.json"
    p.write_text(json.dumps(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)))
    out = tmp_path / "check.json"
    r = subprocess.run([sys.executable, "-m", "limit", "check", str(p), "--ag", "0.25", "--F0", "2.5",
                        "--Tc-star", "0.3", "--soil", "B", "--json", str(out)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    a = json.loads(out.read_text())
    assert a["check"]["linear"]["demand"] == pytest.approx(0.25 * 9.81 * 1.15 / 2, rel=1e-9)
    assert a["demand"]["TC"] == pytest.approx(0.41985, abs=5e-6) and a["demand"]["site"]["soil"] == "B"
    bad = subprocess.run([sys.executable, "-m", "limit", "check", str(p), "--ag", "0.25", "--soil", "B"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "--Tc-star" in bad.stderr


@pytest.mark.slow  # about 6 s: limit check end to end in subprocesses
def test_the_damage_check_at_ground_level_uses_the_sld_hazard_without_q(tmp_path):
    """Circolare 617/2009 C8A.4.7: a0* >= ag(SLD) S, no behaviour factor. With an explicit S = 1.2
    shared by the SLD: 0.08 x 9.81 x 1.2 = 0.94176 m/s^2 (the SLV's linear demand is 0.2 x 9.81 x
    1.2 / 2 = 1.1772). On the site (soil C, the SLD's F0 2.45, ag 0.10 g): SS = 1.70 - 0.60 x 2.45
    x 0.10 = 1.553, clipped to 1.50, so 0.10 x 9.81 x 1.5 = 1.4715 m/s^2, while the SLV (F0 2.4,
    ag 0.25 g) has SS = 1.70 - 0.60 x 2.4 x 0.25 = 1.34. The verdict's ratio is a0* over it."""
    from limit.analysis import analyse
    from scenes import builders as B

    d = from_mapping({"ag_g": 0.2, "S": 1.2, "SLD": {"ag_g": 0.08}})
    assert d.sld.S == 1.2 and d.sld.ag_g == 0.08
    site = from_mapping({"ag_g": 0.25, "F0": 2.4, "Tc_star": 0.3, "soil": "C",
                         "SLD": {"ag_g": 0.10, "F0": 2.45, "Tc_star": 0.25}})
    assert site.S == pytest.approx(1.34) and site.sld.S == pytest.approx(1.5)
    sc = B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)
    sc["demand"] = {"ag_g": 0.2, "S": 1.2, "SLD": {"ag_g": 0.08}}
    v = analyse(load_scene(sc), method="lp").data["verdict"]
    a0 = v["linear"]["a0_star"]
    dm = v["check"]["damage"]
    assert dm["demand"] == pytest.approx(0.08 * 9.81 * 1.2, rel=1e-12)
    assert dm["ratio"] == pytest.approx(a0 / dm["demand"], rel=1e-12) and dm["pass"] == (a0 >= dm["demand"])
    assert v["check"]["linear"]["demand"] == pytest.approx(0.2 * 9.81 * 1.2 / 2, rel=1e-12)
    assert v["demand"]["SLD"]["ag_g"] == 0.08
    p = tmp_path / "block.json"
    p.write_text(json.dumps(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6)))
    r = subprocess.run([sys.executable, "-m", "limit", "check", str(p), "--ag", "0.25", "--F0", "2.4", "--Tc-star",
                        "0.3", "--soil", "C", "--sld-ag", "0.10", "--sld-F0", "2.45", "--sld-Tc-star", "0.25"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "Damage check (SLD, linear)" in r.stdout and "against 1.4715 m/s^2" in r.stdout
    bad = subprocess.run([sys.executable, "-m", "limit", "check", str(p), "--sld-ag", "0.1"], capture_output=True,
                         text=True)
    assert bad.returncode == 2 and "--sld-ag" in bad.stderr


def test_the_damage_check_above_ground_uses_the_floor_demand():
    """C8A.4.8: a0* >= Se(T1) psi(Z) gamma at SLD (no q), at least the ground's ag S. Z = 3 m of
    H = 9 m, N = 3, T1 = 0.3 s (on the plateau, TB = 0.15 <= T1 < TC = 0.5), S = 1, F0 = 2.5:
    Se = 0.08 x 9.81 x 2.5 = 1.962, psi = 1/3, gamma = 9/7: 0.840857 m/s^2 > ag S = 0.7848."""
    from limit.model.seismic_demand import check

    d = from_mapping({"ag_g": 0.2, "Z": 3.0, "H": 9.0, "N": 3, "T1": 0.3, "SLD": {"ag_g": 0.08}})
    c = check(d, a0_star=1.0)
    assert c["damage"]["demand"] == pytest.approx(0.08 * 9.81 * 2.5 / 3 * 9 / 7, rel=1e-12)
    assert c["damage"]["pass"] is True and c["linear"]["demand"] == pytest.approx(0.2 * 9.81 * 2.5 / 3 * 9 / 7 / 2)
    with pytest.raises(ValueError, match=r"demand\.SLD\.Tc_star: required"):
        from_mapping({"ag_g": 0.25, "F0": 2.4, "Tc_star": 0.3, "soil": "C", "SLD": {"ag_g": 0.1, "F0": 2.4}})
