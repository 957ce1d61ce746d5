"""limit/result-1.schema.json against the result files of `limit solve --json` (docs/formats.md,
'Result file'): catalog scenes in 2D and 3D, LP only and with step 2, an infeasible one, and
results that break the contract."""
import copy
import json
from importlib import resources

import fastjsonschema
import pytest

from limit.cli import main
from limit.solve.outcome import RouteOutcome
from scenes.catalog import CATALOG_DIR

#: (scene, extra options, LP status, NLP status or None when step 2 did not run)
CASES = [
    ("block-rocking-2d", ["--method", "lp"], "optimal", None),
    ("side-by-side-2d", [], "optimal", "optimal"),
    ("block-sliding-2d", ["--global", "--iterative-lp"], "optimal", "optimal"),
    ("portal-3d", [], "optimal", "skipped"),
    ("block-sliding-3d", ["--method", "nlp"], "optimal", "optimal"),
    ("paper-fig2a-double-arch-2d", [], "infeasible", "infeasible"),
    ("block-glued-2d", [], "optimal", "optimal"),  # with the Radenkovic lower bound
]


@pytest.fixture(scope="module")
def validate():
    schema = json.loads(resources.files("limit").joinpath("result-1.schema.json").read_text())
    return fastjsonschema.compile(schema)


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = {}
    for name, opts, _, _ in CASES:
        path = tmp_path_factory.mktemp("results") / f"{name}.json"
        assert main(["solve", str(CATALOG_DIR / f"{name}.json"), "--json", str(path), *opts]) == 0
        out[name] = json.loads(path.read_text())
    return out


@pytest.mark.slow  # about 4-6 s: its module fixture solves catalog scenes through the command line
@pytest.mark.parametrize("name,opts,lp_status,nlp_status", CASES, ids=[c[0] for c in CASES])
def test_catalog_results_validate(name, opts, lp_status, nlp_status, results, validate):
    res = results[name]
    assert res["lp"]["status"] == lp_status
    assert res.get("nlp", {}).get("status") == nlp_status
    assert ("lower_bound" in res) == (name == "block-glued-2d")  # only where a joint is bonded
    validate(res)


def _optimal_lp(results):
    return copy.deepcopy(results["side-by-side-2d"])


BROKEN = {
    "no lp": lambda r: r.pop("lp"),
    "no scene": lambda r: r.pop("scene"),
    "no lp status": lambda r: r["lp"].pop("status"),
    "no nlp alpha": lambda r: r["nlp"].pop("alpha"),
    "optimal lp without mechanism": lambda r: r["lp"].pop("mechanism"),
    "n_blocks a string": lambda r: r.update(n_blocks=str(r["n_blocks"])),
    "n_interfaces a float": lambda r: r.update(n_interfaces=r["n_interfaces"] + 0.5),
    "dim 4": lambda r: r.update(dim=4),
    "unknown lp status": lambda r: r["lp"].update(status="done"),
    "lp alpha a string": lambda r: r["lp"].update(alpha=str(r["lp"]["alpha"])),
    "optimal lp with a null alpha": lambda r: r["lp"].update(alpha=None),
    "mechanism with a string": lambda r: r["lp"]["mechanism"].update({next(iter(r["lp"]["mechanism"])): ["0", 0, 0]}),
    "attempt verified a string": lambda r: r["lp"]["attempts"][0].update(verified="yes"),
    "failed nlp without reason": lambda r: r["nlp"].update(status="failed", alpha=None),
}


@pytest.mark.slow  # its module fixture solves catalog scenes through the command line (about 4-6 s)
@pytest.mark.parametrize("fault", BROKEN)
def test_broken_results_fail(fault, results, validate):
    res = _optimal_lp(results)
    validate(res)  # the unbroken copy passes
    BROKEN[fault](res)
    with pytest.raises(fastjsonschema.JsonSchemaValueException):
        validate(res)


def test_a_result_whose_answer_is_the_milp_point_validates(tmp_path, monkeypatch, validate):
    """`limit solve --global --global-time-limit S`, with step 2's own routes made to fail: the
    MILP's checked point is the answer (route "global-milp", tests/test_nlp.py), and the file
    still follows the schema."""
    from limit import step2

    def fail(*a, **k):
        return RouteOutcome(False, reason="stand-in: no verified point")
    monkeypatch.setattr(step2, "run", fail)
    monkeypatch.setattr(step2, "_large", fail)
    path = tmp_path / "r.json"
    assert main(["solve", str(CATALOG_DIR / "side-by-side-2d.json"), "--json", str(path), "--method", "nlp",
                 "--global", "--global-time-limit", "30"]) == 0
    res = json.loads(path.read_text())
    validate(res)
    assert res["nlp"]["route"] == "global-milp" and res["nlp"]["global"]["adopted"] is True
