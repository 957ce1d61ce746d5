"""The solvers: step 1, the associative LP (:mod:`~limit.solve.lp`, the structured interior
point method :mod:`~limit.solve.ipm`, the checked LP with its fallbacks
:mod:`~limit.solve.checked_lp`), and step 2, the non-associative frictional problem
(:mod:`~limit.step2` chooses the route: SLA/NLP with its starts :mod:`~limit.solve.nlp_starts`,
the iterative LP, the global MILP, the large-scale route), with the independent check of every
answer (:mod:`~limit.solve.verify`), and the status of a step (:mod:`~limit.solve.status`).

The LP layer: every solver name a user can give, and the backends of step 2's LPs, are in one
registry (:mod:`~limit.solve.solvers`); step 1's LPs are built in :mod:`~limit.solve.lp`
(cvxpy, or the structured ipm), every other LP of step 2 and the checks (phase 1, the piece
LP, the iterative LP's, the dead-load equilibrium) goes through the matrix front end
:mod:`~limit.solve.lpsub`. The one LP outside is the geometric depth of
:mod:`limit.geom.overlap` (a few unknowns, below this layer)."""
