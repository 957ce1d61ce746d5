"""The validation run's second look where a dynamic engine collapses below step 2: step 2 again,
from that engine's collapse state (:func:`limit.step2.adopt_dem_state`: the contact forces of its
last run's highest equilibrium where the result holds them, and its motion).

Theory brackets a rigid-block collapse between the frictional minimum and the associative LP
(Baggio & Trovalusci, section 3). A dynamic collapse more than :data:`SLACK` below step 2's
alpha is a contradiction: either step 2 stopped above the minimum, or the engine adds something
rigid blocks do not have. The engine's collapse state is tried as a start: where its point
verifies below step 2, it is the limit analysis's answer from then on (the report says where it
came from); where it does not, the contradiction stays and is counted. The limit analysis
compared is the ``cone`` stage's in 3D (the friction cone of both engines) and the ``la``
stage's in 2D. A 3D collapse still below is tried once more on point contacts at the joints'
corners, as both engines carry a joint (:mod:`dem_validation.bracket`). These runs take a few
seconds to a minute each and run only on the contradictions, so they are not cached.
"""
from __future__ import annotations

import sys
import time

#: a dynamic alpha below the frictional one by more than this (relative) is a contradiction
SLACK = 0.01
ENGINES = {"dem": "yade", "lmgc": "lmgc90"}


def la_stage(dim) -> str:
    return "cone" if dim == 3 else "la"


def fric_alpha(la: dict | None) -> float | None:
    """Step 2's alpha in a limit-analysis result (verified, or the LP's point where step 2 was skipped)."""
    nlp = (la or {}).get("nlp") or {}
    return nlp.get("alpha") if nlp.get("status") in ("optimal", "skipped") else None


def below(dynamic: float | None, fric: float | None) -> bool:
    return dynamic is not None and fric is not None and dynamic < fric * (1.0 - SLACK)


def collapse_alpha(res: dict | None) -> float | None:
    res = res or {}
    return res.get("alpha") if res.get("status") == "collapsed" and res.get("displacement") else None


def run(files, results: dict, progress: bool = True) -> dict:
    """{scene: [entry per engine that collapsed below step 2]} from the stage ``results``
    ({(scene, stage): result}); each entry is :func:`limit.step2.adopt_dem_state`'s with ``engine``,
    ``stage``, ``fric_before``, ``dynamic_alpha``, ``time_s``. A fault is recorded as the entry's
    ``status`` "failed" (a failed start is no failed stage: the contradiction stays, counted)."""
    import json
    from pathlib import Path

    out = {}
    for path in files:
        data = json.loads(Path(path).read_text())
        name, dim = data.get("name", Path(path).stem), data.get("dim")
        stage = la_stage(dim)
        la = results.get((name, stage))
        fric = fric_alpha(la)
        entries = []
        for key, engine in ENGINES.items():
            a = collapse_alpha(results.get((name, key)))
            if not below(a, fric):
                continue
            t0 = time.perf_counter()
            try:
                entry = one(data, la, results[(name, key)], engine, stage)
            except Exception as exc:  # noqa: BLE001 - reported, never raised
                entry = {"status": "failed", "alpha": None, "adopted": False, "reason": f"{type(exc).__name__}: {exc}"}
            entry.update(engine=engine, stage=stage, fric_before=fric, dynamic_alpha=a,
                         time_s=time.perf_counter() - t0)
            entries.append(entry)
            if progress:
                got = f"{entry['alpha']:.5g}" if entry.get("alpha") is not None else "-"
                print(f"validate: {name}: {engine} {a:.5g} below step 2's {fric:.5g}; from its collapse state: {got}"
                      f"{' (adopted)' if entry.get('adopted') else ''}", file=sys.stderr)
        if entries:
            out[name] = entries
    return out


def one(data: dict, la: dict, dem: dict, engine: str, stage: str) -> dict:
    """Step 2 from one engine's collapse state, with the limit-analysis stage's friction model. In
    3D (stage "cone"), where the engine's alpha is still below, the entry also gets
    ``point_contacts``: the LP and step 2 from that state on the engines' own joints
    (:func:`dem_validation.bracket.point_contact_state`)."""
    from limit.analysis import solve_lp
    from limit.model.assemble import Options, assemble
    from limit.model.scene import load_scene
    from limit.step2 import adopt_dem_state

    from .stages import CONE_FACES

    model = Options(n_slide=CONE_FACES, slide_fit="inscribed") if stage == "cone" else Options()
    P = assemble(load_scene(data), model)
    sol, _, _ = solve_lp(P)
    from limit.solve.dem_start import state_of

    state = {**state_of(dem), "source": engine}
    _, entry = adopt_dem_state(P, sol, la.get("nlp") or {}, state)
    entry = {k: v for k, v in entry.items() if k != "tried"}
    fric = entry["alpha"] if entry.get("adopted") else fric_alpha(la)
    if stage == "cone" and below(collapse_alpha(dem), fric):
        from dem_validation.bracket import point_contact_state

        entry["point_contacts"] = point_contact_state(P.scene, state)
    return entry


def adopted_alpha(entries) -> float | None:
    """The lowest adopted alpha of a scene's entries (None: none adopted)."""
    got = [e["alpha"] for e in entries or [] if e.get("adopted") and e.get("alpha") is not None]
    return min(got) if got else None
