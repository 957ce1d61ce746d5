"""The solvers: step 1, the associative LP (:mod:`~limit.solve.lp`, the structured interior
point method :mod:`~limit.solve.ipm`, the checked LP with its fallbacks
:mod:`~limit.solve.checked_lp`), and step 2, the non-associative frictional problem
(:mod:`~limit.step2` chooses the route: SLA/NLP, the iterative LP, the global MILP,
the large-scale route), with the independent check of every answer (:mod:`~limit.solve.verify`)."""
