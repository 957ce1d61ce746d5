"""Limit analysis of rigid block assemblies with no-tension, frictional joints.

Data flows one way: scene file -> :mod:`limit.scene` (validated blocks) ->
:mod:`limit.interfaces` (contacts found from the geometry) -> :mod:`limit.loads`
and :mod:`limit.kinematics` (matrices) -> solvers -> results.

The public API::

    import limit
    r = limit.analyse(limit.load_scene("scenes/catalog/block-rocking-2d.json"))
    r.lp.alpha, r.nlp.alpha, r.alpha        # associative bound, frictional, the answer
    r.to_dict()                              # the result file's content (docs/formats.md)

``analyse(scene, method="auto", options=limit.Options(...), ...)``; errors:
:class:`SceneError` (rejected input), :class:`SolverError`; warnings:
:class:`SceneWarning`.
"""

__version__ = "0.1.0"

from .api import Options, Result, StepResult, analyse, load_scene  # noqa: E402
from .errors import SceneError, SceneWarning, SolverError  # noqa: E402

__all__ = ["analyse", "load_scene", "Options", "Result", "StepResult", "SceneError", "SceneWarning",
           "SolverError", "__version__"]
