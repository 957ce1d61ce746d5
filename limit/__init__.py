"""Limit analysis of rigid block assemblies with no-tension, frictional joints.

Data flows one way, through one subpackage per job: the scene file ->
:mod:`limit.model.scene` (validated blocks) -> :mod:`limit.geom` (interfaces found from the
geometry) -> :mod:`limit.model` (loads, kinematics, yield domain, assembled LP data) ->
:mod:`limit.solve` (step 1 and step 2, each answer checked) -> :mod:`limit.results` ->
:mod:`limit.verdict` (the code check, when the scene states a demand). :mod:`limit.analysis`
runs the whole chain and returns the typed result (:mod:`limit.results.typed`); :mod:`limit.api`
is the public face of it.

The public API::

    import limit
    r = limit.analyse(limit.load_scene("scenes/catalog/block-rocking-2d.json"))
    r.lp.alpha, r.nlp.alpha, r.alpha        # associative bound, frictional, the answer
    r.to_dict()                              # the result file's content (docs/formats.md)

``analyse(scene, method="auto", options=limit.Options(...), ...)``; route thresholds, time
budgets and check tolerances: ``limit.Options(settings={"large_min_free": 100})``
(:mod:`limit.settings`, docs/settings.md); errors:
:class:`SceneError` (rejected input), :class:`SolverError`; warnings:
:class:`SceneWarning`.
"""

__version__ = "0.1.0"

from limit.api import CodeCheck, Options, Result, Status, StepResult, Verdict, analyse, load_scene  # noqa: E402
from limit.errors import SceneError, SceneWarning, SolverError  # noqa: E402

__all__ = ["analyse", "load_scene", "Options", "Result", "StepResult", "Status", "Verdict", "CodeCheck", "SceneError",
           "SceneWarning",
           "SolverError", "__version__"]
