"""The outcome of a route of step 2, before it becomes the result file's ``nlp`` part: the
successive LP with its restarts (:func:`limit.step2.run`) and the large-scale route
(:func:`limit.solve.step2_large.solve`)."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class RouteOutcome:
    """``ok``: the best point passed the independent check (:func:`limit.solve.nlp.check`);
    ``alpha``: the best point's load factor (None without a point); ``z``: that point, unknowns
    of the scaled NLP ``N`` (:func:`limit.solve.nlp_problem.build`); ``reason``: why not ok
    (empty where ok); ``runs``: one entry per run (successive LP: start, solver, penalty, alpha,
    verified, reason, time_s; large route: one per start, as ``starts``); ``time_s``: seconds.

    Of the best point where there is one: ``alpha_raw`` (before the piece-LP polish),
    ``residuals`` (the check's), ``notes`` (the solver's and the polish's), ``solver``,
    ``start`` (its label), ``backend`` (the LPs'). The large route only: ``starts`` (per start),
    ``alpha_best``, ``alpha_worst``, ``n_verified`` (over the verified starts) and ``workers``
    (processes)."""

    ok: bool
    alpha: float | None = None
    z: np.ndarray | None = field(default=None, repr=False)
    N: Any = field(default=None, repr=False)
    reason: str = ""
    runs: list = field(default_factory=list, repr=False)
    time_s: float = 0.0
    alpha_raw: float | None = None
    residuals: dict | None = None
    notes: list = field(default_factory=list)
    solver: str | None = None
    start: str | None = None
    backend: str | None = None
    starts: list = field(default_factory=list, repr=False)
    alpha_best: float | None = None
    alpha_worst: float | None = None
    n_verified: int | None = None
    workers: int | None = None

    def replace(self, **changes) -> "RouteOutcome":
        """A new outcome with ``changes``."""
        return dataclasses.replace(self, **changes)
