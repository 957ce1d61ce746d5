"""Limit analysis of rigid block assemblies with no-tension, frictional joints.

Data flows one way: scene file -> :mod:`limit.scene` (validated blocks) ->
:mod:`limit.interfaces` (contacts found from the geometry) -> :mod:`limit.loads`
and :mod:`limit.kinematics` (matrices) -> solvers -> results.
"""

import os

# One BLAS thread: the dense algebra here is small (SLSQP, 2x2 to 6x6 blocks), runs are
# parallelised by process, and a multi-threaded OpenBLAS on a busy machine was measured
# to slow SLSQP down 300-fold. Set before numpy is imported; an explicit setting wins.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

__version__ = "0.1.0"
