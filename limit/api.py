"""The public API: :func:`analyse` returns a typed :class:`Result` (the result file's
content as attributes, :meth:`Result.to_dict` for the file itself; the classes are those of
:mod:`limit.results.typed`)."""
from __future__ import annotations

from limit.model.assemble import Options
from limit.model.scene import load_scene
from limit.results.typed import CodeCheck, Result, StepResult, Verdict
from limit.solve.status import Status

__all__ = ["analyse", "load_scene", "Options", "Result", "StepResult", "CodeCheck", "Verdict", "Status"]


def analyse(scene, method: str = "auto", options: Options | None = None, **kw) -> Result:
    """Limit analysis of a scene (a :class:`limit.model.scene.Scene`, a path or a parsed dict).
    ``method``: "lp" (step 1 only), "nlp" (always step 2) or "auto" (step 2 where it can
    change the answer); further keywords as :func:`limit.analysis.analyse`."""
    from limit.analysis import analyse as _analyse
    from limit.model.scene import Scene

    if not isinstance(scene, Scene):
        scene = load_scene(scene)
    return _analyse(scene, method=method, options=options, **kw).result
