"""Results: the parts of the result file built from a solution (:mod:`~limit.results.result_parts`),
the one-line summary, and the interface report of ``limit info``."""
