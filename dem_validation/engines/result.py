"""The typed DEM result of any engine, and its ``dem`` dict (docs/formats.md, 'Result file').

A :class:`DemResult` keeps the keys it was given in the order it was given them,
so :meth:`DemResult.to_dict` writes the same dict, key for key and in the same order,
whichever engine built it; keys it has no field for are kept in ``extra``.
"""
from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from typing import Any


class Status(str, enum.Enum):
    """How a DEM run ended."""

    COLLAPSED = "collapsed"
    STABLE = "stable"  # no collapse up to alpha_max, or nothing can move
    FAILED = "failed"  # with a reason: engine missing, crashed, timed out, inconsistent runs
    SKIPPED = "skipped"  # with a reason: the scene needs what the engine does not model


#: the note of a scene without a free block (both engines)
NOTHING_FREE = "no free block: nothing can move"


@dataclass(frozen=True)
class DemResult:
    """One engine's ``dem`` result; a field that is None and not in ``keys`` is absent."""

    status: Status
    alpha: float | None = None
    alpha_uncertainty: float | None = None
    reason: str | None = None
    note: str | None = None
    dead_load_collapse: bool | None = None
    extrapolation: dict | None = None
    displacement: dict | None = None
    runs: list | None = None
    history: list | None = None
    steps: int | None = None
    steps_total: int | None = None
    cpu_s: float | None = None
    fixed_addresses: bool | None = None
    penetration_ratio: float | None = None
    runs_used: list | None = None
    progress: dict | None = None
    time_s: float | None = None
    engine: str | None = None
    params: dict | None = None
    contact: str | None = None
    #: keys without a field, in order
    extra: tuple[tuple[str, Any], ...] = ()
    #: the keys of the dict, in order
    keys: tuple[str, ...] = ()

    @classmethod
    def of(cls, status: Status | str, **fields) -> DemResult:
        """A result with ``status`` and ``fields``, in this order."""
        return cls(status=Status(status)).with_(**fields)

    @classmethod
    def from_dict(cls, d: dict) -> DemResult:
        """The result of a ``dem`` dict (its ``status`` one of :class:`Status`)."""
        fields = dict(d)
        status = fields.pop("status")
        out = cls.of(status, **fields)
        return dataclasses.replace(out, keys=tuple(d))

    def with_(self, **fields) -> DemResult:
        """This result with ``fields`` set; new keys come last (as dict.update)."""
        own = {f.name for f in dataclasses.fields(self)} - {"status", "extra", "keys"}
        extra = dict(self.extra)
        changes = {}
        for k, v in fields.items():
            if k == "status":
                changes[k] = Status(v)
            elif k in own:
                changes[k] = v
            else:
                extra[k] = v
        keys = self.keys or ("status",)
        keys = keys + tuple(k for k in fields if k not in keys)
        return dataclasses.replace(self, **changes, extra=tuple(extra.items()), keys=keys)

    def get(self, key: str, default=None):
        """The value of ``key`` in :meth:`to_dict`, or ``default``."""
        if key not in self.keys:
            return default
        if key == "status":
            return self.status.value
        extra = dict(self.extra)
        return extra[key] if key in extra else getattr(self, key)

    def to_dict(self) -> dict:
        """The ``dem`` dict: status as its string, every key in order."""
        return {k: self.get(k) for k in self.keys}


def failed(reason: str, **extra) -> DemResult:
    """A failed result with a one-line ``reason``."""
    return DemResult.of(Status.FAILED, reason=" ".join(str(reason).split()), **extra)


def nothing_free(**stamp) -> DemResult:
    """The result of a scene without a free block."""
    return DemResult.of(Status.STABLE, alpha=None, note=NOTHING_FREE, time_s=0.0, **stamp)


def skipped(reason: str, **stamp) -> DemResult:
    """The result of a scene the engine does not model (``reason``: what it lacks)."""
    return DemResult.of(Status.SKIPPED, alpha=None, reason=reason, time_s=0.0, **stamp)
