"""The public API: :func:`analyse` returns a typed :class:`Result` (the result file's
content as attributes, :meth:`Result.to_dict` for the file itself)."""
from __future__ import annotations

from dataclasses import dataclass, field

from .assemble import Options
from .scene import load_scene

__all__ = ["analyse", "load_scene", "Options", "Result", "StepResult"]


@dataclass(frozen=True)
class StepResult:
    """One step of the analysis (``lp``: step 1, ``nlp``: step 2).

    ``status``: optimal | skipped (step 2 cannot change the LP's answer) | infeasible (the
    dead load alone collapses) | unbounded (no mechanism) | failed (with ``reason``);
    ``alpha``: the load factor (None unless the status carries one); ``mechanism``: block
    id -> velocity (2D [ux, uy, rz], 3D [ux, uy, uz, rx, ry, rz]; unit work of the live load);
    ``data``: the whole part of the result file."""

    status: str
    alpha: float | None
    time_s: float | None
    reason: str
    mechanism: dict | None
    data: dict = field(repr=False)

    @classmethod
    def from_dict(cls, d: dict | None) -> "StepResult | None":
        if d is None:
            return None
        return cls(d.get("status"), d.get("alpha"), d.get("time_s"), d.get("reason", ""), d.get("mechanism"), d)


@dataclass(frozen=True)
class Result:
    """The limit analysis of one scene. ``alpha``: the answer (the frictional step 2 where
    it ran or was skipped, else the LP's bound); ``lp``, ``nlp``: :class:`StepResult`."""

    scene: str
    dim: int
    n_blocks: int
    n_free_blocks: int
    n_interfaces: int
    lp: StepResult
    nlp: StepResult | None
    _data: dict = field(repr=False)

    @property
    def alpha(self) -> float | None:
        if self.nlp is not None and self.nlp.status in ("optimal", "skipped"):
            return self.nlp.alpha
        return self.lp.alpha if self.nlp is None else None

    def to_dict(self) -> dict:
        """The result file's content (JSON-ready: docs/formats.md, 'Result file')."""
        from .analysis import public

        return public(self._data)


def analyse(scene, method: str = "auto", options: Options | None = None, **kw) -> Result:
    """Limit analysis of a scene (a :class:`limit.scene.Scene`, a path or a parsed dict).
    ``method``: "lp" (step 1 only), "nlp" (always step 2) or "auto" (step 2 where it can
    change the answer); further keywords as :func:`limit.analysis.analyse`."""
    from .analysis import analyse as _analyse
    from .scene import Scene

    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    d = _analyse(scene, method=method, options=options, **kw)
    return Result(d["scene"], d["dim"], d["n_blocks"], d["n_free_blocks"], d["n_interfaces"],
                  StepResult.from_dict(d["lp"]), StepResult.from_dict(d.get("nlp")), d)
