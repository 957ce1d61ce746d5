"""The public API: :func:`analyse` returns a typed :class:`Result` (the result file's
content as attributes, :meth:`Result.to_dict` for the file itself)."""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

from limit.model.assemble import Options
from limit.model.scene import load_scene
from limit.solve.status import ANSWERED, Status

__all__ = ["analyse", "load_scene", "Options", "Result", "StepResult", "CodeCheck", "Verdict", "Status"]


@dataclass(frozen=True)
class StepResult:
    """One step of the analysis (``lp``: step 1, ``nlp``: step 2).

    ``status``: a :class:`Status`: optimal | skipped (the LP's mechanism has no sliding and its
    point passed the frictional check: it is the answer) | infeasible (the dead load alone
    collapses) | unbounded (no mechanism) | failed (with ``reason``);
    ``alpha``: the load factor (None unless the status carries one); ``mechanism``: block
    id -> velocity (2D [ux, uy, rz], 3D [ux, uy, uz, rx, ry, rz]; unit work of the live load);
    ``data``: the whole part of the result file."""

    status: Status
    alpha: float | None
    time_s: float | None
    reason: str
    mechanism: dict | None
    data: dict = field(repr=False)

    @classmethod
    def from_dict(cls, d: dict | None) -> "StepResult | None":
        if d is None:
            return None
        return cls(Status(d["status"]), d.get("alpha"), d.get("time_s"), d.get("reason", ""), d.get("mechanism"), d)


@dataclass(frozen=True)
class CodeCheck:
    """One check of the Circolare 2019, C8.7.1: ``demand`` and ``capacity`` (m/s^2 for the
    linear check, m for the nonlinear one), ``ratio`` = capacity / demand, ``passed``."""

    demand: float
    capacity: float
    ratio: float
    passed: bool

    @classmethod
    def from_dict(cls, d: dict | None) -> "CodeCheck | None":
        return None if d is None else cls(d["demand"], d["capacity"], d["ratio"], bool(d["pass"]))


@dataclass(frozen=True)
class Verdict:
    """The code check of the collapse mechanism against the scene's seismic demand.

    ``status``: done | failed (with ``reason``); ``step``: whose mechanism (nlp or lp);
    ``alpha0``: its load factor; ``a0_star``: the spectral acceleration capacity (m/s^2);
    ``M_star`` (kg), ``e_star``: participating mass and its fraction; ``linear``,
    ``nonlinear``: :class:`CodeCheck` (``nonlinear`` None with ``nonlinear_reason``);
    ``passed``: every check made passed; ``data``: the whole ``verdict`` part."""

    status: str
    reason: str
    step: str | None
    alpha0: float | None
    a0_star: float | None
    M_star: float | None
    e_star: float | None
    linear: CodeCheck | None
    nonlinear: CodeCheck | None
    nonlinear_reason: str
    data: dict = field(repr=False)

    @property
    def passed(self) -> bool | None:
        made = [c for c in (self.linear, self.nonlinear) if c is not None]
        return all(c.passed for c in made) if made else None

    @classmethod
    def from_dict(cls, d: dict | None) -> "Verdict | None":
        if d is None:
            return None
        lin, chk = d.get("linear") or {}, d.get("check") or {}
        return cls(d.get("status"), d.get("reason", ""), d.get("step"), d.get("alpha0"), lin.get("a0_star"),
                   lin.get("M_star"), lin.get("e_star"), CodeCheck.from_dict(chk.get("linear")),
                   CodeCheck.from_dict(chk.get("nonlinear")), chk.get("nonlinear_reason", "") or "", d)


@dataclass(frozen=True)
class Result:
    """The limit analysis of one scene. ``alpha``: the answer (the frictional step 2 where
    it ran or was skipped, else the LP's bound); ``lp``, ``nlp``: :class:`StepResult`;
    ``verdict``: :class:`Verdict` when the scene states a demand, else None."""

    scene: str
    dim: int
    n_blocks: int
    n_free_blocks: int
    n_interfaces: int
    lp: StepResult
    nlp: StepResult | None
    _data: dict = field(repr=False)
    verdict: Verdict | None = None

    @property
    def alpha(self) -> float | None:
        if self.nlp is not None and self.nlp.status in ANSWERED:
            return self.nlp.alpha
        return self.lp.alpha if self.nlp is None else None

    def raise_for_status(self) -> "Result":
        """This result, or :class:`limit.errors.SolverError` when it has no trustworthy answer: a
        step whose status is "failed" (the case in which ``limit solve`` exits 1), naming the step
        and its reason. An infeasible or unbounded LP is an answer (the dead load alone collapses;
        no mechanism) and raises nothing: its ``alpha`` is None. :func:`analyse` itself never
        raises SolverError: a failed step is a status of its result."""
        from limit.errors import SolverError

        for name, part in (("LP", self.lp), ("step 2", self.nlp)):
            if part is not None and part.status == Status.FAILED:
                raise SolverError(f"{self.scene}: {name} {part.status}" + (f": {part.reason}" if part.reason else ""))
        return self

    def to_dict(self) -> dict:
        """The result file's content (JSON-ready: docs/formats.md, 'Result file'), a copy."""
        return copy.deepcopy(self._data)


def analyse(scene, method: str = "auto", options: Options | None = None, **kw) -> Result:
    """Limit analysis of a scene (a :class:`limit.model.scene.Scene`, a path or a parsed dict).
    ``method``: "lp" (step 1 only), "nlp" (always step 2) or "auto" (step 2 where it can
    change the answer); further keywords as :func:`limit.analysis.analyse`."""
    from limit.analysis import analyse as _analyse
    from limit.model.scene import Scene

    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    d = _analyse(scene, method=method, options=options, **kw).data
    return Result(d["scene"], d["dim"], d["n_blocks"], d["n_free_blocks"], d["n_interfaces"],
                  StepResult.from_dict(d["lp"]), StepResult.from_dict(d.get("nlp")), d,
                  Verdict.from_dict(d.get("verdict")))
