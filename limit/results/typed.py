"""The typed results of an analysis: :class:`StepResult` (one step: the LP, step 2),
:class:`Verdict` with its :class:`CodeCheck`\\ s, and :class:`Result` (a whole analysis).

Each is a frozen dataclass, made once and never changed: a step's part is revised by making a
new one (:meth:`StepResult.updated`). The result file (docs/formats.md, 'Result file') is
written from them (:meth:`Result.to_dict`). A :class:`StepResult` also reads as a read-only mapping of its part of the file
(``part["alpha"]``, ``part.get("runs")``), so code that reads a part's keys reads either.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from limit.solve.status import ANSWERED, Status

#: the typed fields of a step's part, in the order the file gives them
_STEP_FIELDS = ("status", "alpha", "time_s", "reason", "mechanism")


@dataclass(frozen=True)
class StepResult(Mapping):
    """One step of the analysis (``lp``: step 1, ``nlp``: step 2).

    ``status``: a :class:`Status`: optimal | skipped (the LP's mechanism has no sliding and its
    point passed the frictional check: it is the answer) | infeasible (the dead load alone
    collapses) | unbounded (no mechanism) | failed (with ``reason``);
    ``alpha``: the load factor (None unless the status carries one); ``time_s``: seconds;
    ``reason``: why (empty where there is nothing to say); ``mechanism``: block id -> velocity
    (2D [ux, uy, rz], 3D [ux, uy, uz, rx, ry, rz]; unit work of the live load), or None;
    ``details``: the part's other keys (JSON-ready values: docs/formats.md, 'Result file')."""

    status: Status
    alpha: float | None = None
    time_s: float | None = None
    reason: str = ""
    mechanism: Mapping | None = None
    details: Mapping[str, Any] = field(default_factory=dict, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "status", Status(self.status))
        object.__setattr__(self, "details", MappingProxyType(dict(self.details)))

    @classmethod
    def from_dict(cls, d: Mapping | None) -> "StepResult | None":
        """The step of a result file's part (None for None); a StepResult is returned as it is."""
        if d is None or isinstance(d, StepResult):
            return d
        return cls(d["status"], d.get("alpha"), d.get("time_s"), d.get("reason") or "", d.get("mechanism"),
                   {k: v for k, v in d.items() if k not in _STEP_FIELDS})

    def updated(self, **changes) -> "StepResult":
        """A new step with ``changes`` applied (typed fields or detail keys); a key given
        :data:`DROP` is removed (a typed field goes back to its default)."""
        cur = {"status": self.status, "alpha": self.alpha, "time_s": self.time_s, "reason": self.reason,
               "mechanism": self.mechanism}
        defaults = {"alpha": None, "time_s": None, "reason": "", "mechanism": None}
        for k in _STEP_FIELDS:
            if k in changes:
                v = changes.pop(k)
                cur[k] = defaults.get(k) if v is DROP else v
        cur["reason"] = cur["reason"] or ""
        details = {k: v for k, v in {**self.details, **changes}.items() if v is not DROP}
        return StepResult(**cur, details=details)

    def without(self, *keys: str) -> "StepResult":
        """A new step without ``keys``."""
        return self.updated(**{k: DROP for k in keys})

    @property
    def data(self) -> dict:
        """The part of the result file (a new dict; as :meth:`to_dict`)."""
        return self.to_dict()

    def to_dict(self) -> dict:
        """The part of the result file: ``status``, ``alpha``, ``time_s``, then ``reason`` and
        ``mechanism`` where given, then the details (a new top-level dict)."""
        out = {"status": self.status, "alpha": self.alpha, "time_s": self.time_s}
        if self.reason:
            out["reason"] = self.reason
        if self.mechanism is not None:
            out["mechanism"] = self.mechanism
        out.update(self.details)
        return out

    # the read-only mapping of the part (Mapping supplies get, keys, items, values, ==)
    def __getitem__(self, key: str):
        if key in ("status", "alpha", "time_s"):
            return getattr(self, key)
        if key == "reason" and self.reason:
            return self.reason
        if key == "mechanism" and self.mechanism is not None:
            return self.mechanism
        return self.details[key]

    def __iter__(self):
        return iter(self.to_dict())

    def __len__(self) -> int:
        return len(self.to_dict())

    def __eq__(self, other):
        if isinstance(other, Mapping):
            return self.to_dict() == dict(other)
        return NotImplemented

    __hash__ = None


class _Drop:
    def __repr__(self):
        return "DROP"


#: a value for :meth:`StepResult.updated` that removes a detail key
DROP = _Drop()


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
    data: Mapping = field(repr=False)

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
                   CodeCheck.from_dict(chk.get("nonlinear")), chk.get("nonlinear_reason", "") or "",
                   MappingProxyType(dict(d)))


@dataclass(frozen=True)
class Result:
    """The limit analysis of one scene, as :func:`limit.analysis.analyse` makes it. ``alpha``: the
    answer (the frictional step 2 where it ran or was skipped, else the LP's bound); ``lp``,
    ``nlp``: :class:`StepResult` (``nlp`` None where step 2 was not asked for); ``units``: of
    every number (the result file's ``units``); ``lower_bound``: the cohesive scene's lower bound
    part, or None; ``verdict``: :class:`Verdict` when the scene states a demand, else None."""

    scene: str
    dim: int
    n_blocks: int
    n_free_blocks: int
    n_interfaces: int
    lp: StepResult
    nlp: StepResult | None = None
    units: Mapping = field(default_factory=dict, repr=False)
    lower_bound: Mapping | None = field(default=None, repr=False)
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
        no mechanism) and raises nothing: its ``alpha`` is None. :func:`limit.analyse` itself
        never raises SolverError: a failed step is a status of its result."""
        from limit.errors import SolverError

        for name, part in (("LP", self.lp), ("step 2", self.nlp)):
            if part is not None and part.status == Status.FAILED:
                raise SolverError(f"{self.scene}: {name} {part.status}" + (f": {part.reason}" if part.reason else ""))
        return self

    def to_dict(self) -> dict:
        """The result file's content (JSON-ready: docs/formats.md, 'Result file'), a new dict
        whose nested values are the parts' own."""
        out = {"scene": self.scene, "dim": self.dim, "n_blocks": self.n_blocks, "n_free_blocks": self.n_free_blocks,
               "n_interfaces": self.n_interfaces, "units": dict(self.units), "lp": self.lp.to_dict()}
        if self.nlp is not None:
            out["nlp"] = self.nlp.to_dict()
        if self.lower_bound is not None:
            out["lower_bound"] = dict(self.lower_bound)
        if self.verdict is not None:
            out["verdict"] = dict(self.verdict.data)
        return out
