"""Limit analysis of rigid block assemblies with no-tension, frictional joints.

Data flows one way: scene file -> :mod:`limit.scene` (validated blocks) ->
:mod:`limit.interfaces` (contacts found from the geometry) -> :mod:`limit.loads`
and :mod:`limit.kinematics` (matrices) -> solvers -> results.
"""

__version__ = "0.1.0"
