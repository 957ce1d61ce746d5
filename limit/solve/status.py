"""The status of a step of the analysis: of an LP solution (:class:`limit.solve.lp.LPSolution`)
and of the result file's ``lp``, ``nlp``, ``lower_bound`` and ``nlp.dem_start`` parts
(docs/formats.md, 'Result file').

A :class:`enum.StrEnum`: a member is its string (``Status.OPTIMAL == "optimal"``), and JSON,
``str()`` and f-strings give the value, so a result file reads the same as with bare strings.
The independent checks keep their own words (the MILP's "time_limit", the iterative LP's
"converged"), as do the code check ("done") and the tie design ("out_of_reach")."""
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
