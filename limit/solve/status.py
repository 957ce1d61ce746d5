"""The status of a step of the analysis: of an LP solution (:class:`limit.solve.lp.LPSolution`)
and of the result file's ``lp``, ``nlp``, ``lower_bound`` and ``nlp.dem_start`` parts
(docs/formats.md, 'Result file').

A :class:`enum.StrEnum`: a member is its string (``Status.OPTIMAL == "optimal"``), and JSON,
``str()`` and f-strings give the value, so a result file reads the same as with bare strings.
The independent checks and the solvers inside a step have words of their own, each an enum
below: the MILP's (:class:`GlobalStatus`), the iterative LP's (:class:`IterativeStatus`), the
interior point method's (:class:`IpmStatus`), and the code check's and tie design's
(:class:`CheckStatus`)."""
from __future__ import annotations

from enum import StrEnum


class Status(StrEnum):
    #: solved and checked: ``alpha`` is the step's answer
    OPTIMAL = "optimal"
    #: step 2 not run: the LP's point passed the frictional check and is the answer
    SKIPPED = "skipped"
    #: no trustworthy answer (the ``reason`` says why)
    FAILED = "failed"
    #: the dead load alone collapses the assembly
    INFEASIBLE = "infeasible"
    #: no mechanism: the live load is carried at any multiplier
    UNBOUNDED = "unbounded"
    #: an LP solver's answer still to be verified (:mod:`limit.solve.checked_lp`); never in a result
    INACCURATE = "inaccurate"


#: the statuses of step 2 whose ``alpha`` is the frictional answer
ANSWERED = (Status.OPTIMAL, Status.SKIPPED)


class GlobalStatus(StrEnum):
    """The mixed-integer global minimum (:func:`limit.solve.milp.global_minimum`)."""

    #: the proven global optimum (relative gap 1e-7)
    OPTIMAL = "optimal"
    #: stopped at its time limit: the best point so far (``alpha``, may be None) and the proven ``bound``
    TIME_LIMIT = "time_limit"
    INFEASIBLE = "infeasible"
    UNBOUNDED = "unbounded"
    FAILED = "failed"


class IterativeStatus(StrEnum):
    """The iterative LP of Gilbert et al. (:mod:`limit.solve.iterative_lp`)."""

    #: the normal forces stopped changing
    CONVERGED = "converged"
    #: still changing after the last LP allowed
    NOT_CONVERGED = "not_converged"
    #: stopped by its caller (a time budget)
    STOPPED = "stopped"
    FAILED = "failed"


class IpmStatus(StrEnum):
    """One solve of the structured interior point method (:func:`limit.solve.ipm.solve`)."""

    OPTIMAL = "optimal"
    #: not converged, but its best iterate's residual is within the caller's ``almost``
    ALMOST = "almost"
    FAILED = "failed"


class CheckStatus(StrEnum):
    """The code check (:func:`limit.verdict.local_check.scene_verdict`) and the tie design
    (:mod:`limit.tie_design`)."""

    DONE = "done"
    FAILED = "failed"
    #: tie design: no tie layout reaches the target
    INFEASIBLE = "infeasible"
    #: tie design: step 2 stays below the target with every capacity allowed
    OUT_OF_REACH = "out_of_reach"
