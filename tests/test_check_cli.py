"""``limit check`` and ``limit sweep`` end to end (exit statuses, numbers against
limit.verdict.kinematic_check's hand-checked values, JSON written)."""
import json

import pytest

from limit.cli import main
from scenes import builders as B


def _write(tmp_path, data, name="s.json"):
    p = tmp_path / name
    p.write_text(json.dumps(data))
    return str(p)


def test_check_of_one_block_with_a_demand(tmp_path, capsys):
    """0.3 x 1 block: alpha0 = 0.3, e* = 1, a0* = 0.3 9.81 / 1.35 = 2.18 m/s^2 against
    ag S / q = 0.25 9.81 1.2 / 2 = 1.4715: passes; the capacity curve gives du* = 0.06 m."""
    f = _write(tmp_path, B.single_block(2, 0.3, 1.0, mu=0.8))
    out = tmp_path / "a.json"
    assert main(["check", f, "--ag", "0.25", "--S", "1.2", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "PASS" in text and "e* = 1.0000" in text
    a = json.loads(out.read_text())
    assert a["linear"]["a0_star"] == pytest.approx(0.3 * 9.81 / 1.35, rel=1e-6)
    assert a["check"]["linear"]["demand"] == pytest.approx(1.4715)
    assert a["curve"]["spectral"]["du_star"] == pytest.approx(0.06, rel=1e-6)


def test_check_bad_inputs_exit_2_and_no_mechanism_exit_1(tmp_path, capsys):
    f = _write(tmp_path, B.single_block(2, 0.3, 1.0, mu=0.8))
    assert main(["check", f, "--ag", "-1"]) == 2
    assert "--ag: must be a positive number" in capsys.readouterr().err
    assert main(["check", f, "--fc", "0.5"]) == 2
    assert main(["check", f, "--ag", "0.2", "--Z", "3"]) == 2  # above ground needs H, N, T1
    err = capsys.readouterr().err
    assert "--fc" in err and "above ground" in err
    wedged = _write(tmp_path, B.confined_block(2), "c.json")  # LP unbounded, step 2 gives the mechanism
    assert main(["check", wedged, "--method", "lp"]) == 1
    assert "no mechanism" in capsys.readouterr().err


def test_sweep_command(tmp_path, capsys):
    f = _write(tmp_path, B.single_block(3, 0.3, 1.0, t=0.3, mu=0.8))
    out = tmp_path / "w.json"
    assert main(["sweep", f, "--step", "45", "--jobs", "1", "--json", str(out)]) == 0
    r = json.loads(out.read_text())
    assert len(r["theta"]) == 8 and r["min_alpha"] == pytest.approx(0.3, rel=1e-6)
    assert "minimum LP alpha 0.3" in capsys.readouterr().out
    assert main(["sweep", _write(tmp_path, B.single_block(2), "d.json")]) == 2
    assert main(["sweep", f, "--step", "0"]) == 2


def test_a_scene_with_a_demand_gets_a_verdict_in_its_result_file(tmp_path, capsys):
    """The 0.3 x 1 block with "demand": {"ag_g": 0.25, "S": 1.2} in the scene: ``limit solve``
    writes a verdict (a0* = 0.3 9.81 / 1.35 = 2.18 m/s^2 against 1.4715: passes). A strong
    site (ag 0.5 g, S 1.5: 0.5 9.81 1.5 / 2 = 3.679 m/s^2) fails, ratio 2.18 / 3.679 = 0.593.
    ``limit check --ag`` overrides the scene's demand. A scene without a demand has no verdict
    (no work spent)."""
    data = B.single_block(2, 0.3, 1.0, mu=0.8)
    a0 = 0.3 * 9.81 / 1.35
    for ag, S, ok in ((0.25, 1.2, True), (0.5, 1.5, False)):
        f = _write(tmp_path, dict(data, demand={"ag_g": ag, "S": S}))
        out = tmp_path / "r.json"
        assert main(["solve", f, "--json", str(out)]) == 0
        v = json.loads(out.read_text())["verdict"]
        li = v["check"]["linear"]
        assert v["status"] == "done" and li["pass"] is ok
        assert li["ratio"] == pytest.approx(a0 / (ag * 9.81 * S / 2), rel=1e-6)
        assert v["curve"]["spectral"]["du_star"] == pytest.approx(0.06, rel=1e-6)
    capsys.readouterr()
    assert main(["check", f, "--ag", "0.25", "--S", "1.2", "--json", str(tmp_path / "c.json")]) == 0
    assert json.loads((tmp_path / "c.json").read_text())["check"]["linear"]["pass"] is True
    assert main(["solve", _write(tmp_path, data, "plain.json"), "--json", str(tmp_path / "p.json")]) == 0
    assert "verdict" not in json.loads((tmp_path / "p.json").read_text())


def test_check_follows_the_mechanism_once_with_either_demand(tmp_path, monkeypatch, capsys):
    """A scene stating a demand, checked with its own demand and with ``--ag``: the capacity
    curve is followed once either way (the scene's check is not made and then replaced), and
    the demand used is the one asked for (0.4 9.81 1.2 / 2 = 2.3544 m/s^2 with --ag 0.4)."""
    from limit.verdict import capacity_curve

    calls = []
    real = capacity_curve.follow
    monkeypatch.setattr(capacity_curve, "follow", lambda *a, **k: calls.append(1) or real(*a, **k))
    f = _write(tmp_path, dict(B.single_block(2, 0.3, 1.0, mu=0.8), demand={"ag_g": 0.25, "S": 1.2}))
    for extra, need in (([], 0.25 * 9.81 * 1.2 / 2), (["--ag", "0.4", "--S", "1.2"], 0.4 * 9.81 * 1.2 / 2)):
        calls.clear()
        out = tmp_path / "a.json"
        assert main(["check", f, *extra, "--json", str(out)]) == 0
        assert len(calls) == 1
        assert json.loads(out.read_text())["check"]["linear"]["demand"] == pytest.approx(need, rel=1e-9)
    capsys.readouterr()


def test_a_bad_demand_in_a_scene_is_named(tmp_path, capsys):
    data = B.single_block(2, 0.3, 1.0, mu=0.8)
    for demand, key in (({"ag_g": 0.2, "TB": 0.6}, "TB < TC < TD"), ({"ag_g": 0.2, "Z": 3.0}, "above ground"),
                        ({"S": 1.2}, "ag_g"), ({"ag_g": -0.2}, "ag_g"), ({"ag_g": 0.2, "fc": 0.5}, "fc"),
                        ({"ag_g": 0.2, "xi1": 5.0}, "xi1")):
        assert main(["solve", _write(tmp_path, dict(data, demand=demand))]) == 2
        assert key in capsys.readouterr().err


def test_the_nonlinear_check_above_ground_uses_the_floor_spectrum(tmp_path):
    """A scene's demand above ground (with the building's damping xi1 given) gives the nonlinear
    check of the 2019 Circolare: du* against the floor displacement spectrum at T_SLV."""
    from limit.model.seismic_demand import Demand

    dem = {"ag_g": 0.2, "Z": 3.0, "H": 9.0, "N": 3, "T1": 0.3, "xi1": 0.1}
    data = dict(B.single_block(2, 0.3, 1.0, mu=0.8), demand=dem)
    out = tmp_path / "r.json"
    assert main(["solve", _write(tmp_path, data), "--json", str(out)]) == 0
    c = json.loads(out.read_text())["verdict"]["check"]
    nl = c["nonlinear"]
    assert nl is not None and nl["rule"] == "SDeZ(T_SLV)" and c["nonlinear_reason"] == ""
    assert nl["demand"] == pytest.approx(Demand(**dem).SDeZ(nl["period"]))
    assert nl["capacity"] == pytest.approx(0.06, rel=1e-6)  # 0.4 d0*, d0* = b/2 (e* = 1)


def test_a_damping_ratio_in_percent_is_refused(tmp_path, capsys):
    f = _write(tmp_path, B.single_block(2, 0.3, 1.0, mu=0.8))
    assert main(["check", f, "--ag", "0.2", "--Z", "3", "--H", "9", "--N", "3", "--T1", "0.3", "--xi1", "5"]) == 2
    assert "--xi1" in capsys.readouterr().err


def test_check_without_options_uses_the_scene_s_own_demand(tmp_path, capsys):
    """A scene stating ag = 0.5 g, S = 1.5 (demand 0.5 9.81 1.5 / 2 = 3.679 m/s^2): ``limit check``
    with no spectrum option reports that check (the 0.3 x 1 block fails it, ratio 0.593)."""
    f = _write(tmp_path, dict(B.single_block(2, 0.3, 1.0, mu=0.8), demand={"ag_g": 0.5, "S": 1.5}))
    out = tmp_path / "a.json"
    assert main(["check", f, "--json", str(out)]) == 0
    li = json.loads(out.read_text())["check"]["linear"]
    assert li["demand"] == pytest.approx(0.5 * 9.81 * 1.5 / 2) and li["pass"] is False
    assert li["ratio"] == pytest.approx((0.3 * 9.81 / 1.35) / (0.5 * 9.81 * 1.5 / 2), rel=1e-6)
    assert "FAIL" in capsys.readouterr().out
