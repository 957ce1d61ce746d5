"""The LP solver registry: every solver name a user can give for step 1 (``--solver``),
what it is, the fallback order when an answer fails its check, and the backends of the
small sparse LPs of step 2 (:mod:`limit.solve.lpsub`). Importable without cvxpy, so the
command line reads its choices from here; :mod:`limit.solve.lp` maps the names onto
cvxpy and :mod:`limit.solve.ipm`. The defaults come from ``make bench`` (bench/lp_bench.py).
"""
from __future__ import annotations

#: step 1: name -> what it is ("auto" picks ipm or clarabel by size)
STEP1 = {
    "auto": "ipm from lp_ipm_min_dof block unknowns on (limit.settings), clarabel below",
    "ipm": "the structured interior point method of limit.solve.ipm (interface-by-interface elimination)",
    "clarabel": "Clarabel through cvxpy (interior point, qdldl factorisation)",
    "ecos": "ECOS through cvxpy (interior point)",
    "highs": "HiGHS through cvxpy (its own choice: dual simplex on LPs)",
    "highs-ipm": "HiGHS's interior point through cvxpy, no crossover",
}
SOLVERS = tuple(STEP1)
DEFAULT_SOLVER = "auto"
#: solvers tried in turn when an answer fails its verification
FALLBACK = {"clarabel": ["highs-ipm", "ecos"], "ecos": ["clarabel"], "highs": ["clarabel"],
            "highs-ipm": ["clarabel"], "ipm": ["clarabel", "highs-ipm"]}
#: step 2's small sparse LPs (limit.solve.lpsub): scipy's HiGHS (exact vertices) or Clarabel's own API
SUBPROBLEM_BACKENDS = ("highs", "clarabel")
