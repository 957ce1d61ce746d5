"""Load checks that need the built blocks (docs/formats.md, 'Scene file', rejections):

* a point force's ``point`` outside its block by more than the geometric tolerance;
* a live load that does no work on any free block (a zero direction or force, a load on fixed
  blocks only, on blocked dofs only, or loads that cancel): alpha would multiply nothing.

Each raises :class:`~limit.errors.SceneError` naming the load.
"""
from __future__ import annotations

import numpy as np

from limit.errors import SceneError
from limit.model.hull_distance import inside, point_to_hull


class NoLiveWork(SceneError):
    """The live load does no work on any free block (a rejection; the direction sweep reads it as
    "no mechanism in this direction")."""


def check_loads(scene) -> None:
    """Both checks on a built :class:`~limit.model.scene.Scene`."""
    for case in ("dead", "live"):
        for k, ld in enumerate(getattr(scene, case)):
            if ld["type"] == "point_force" and "point" in ld:
                check_point(scene, ld, f"loads.{case}[{k}]")
    check_live_work(scene)


def check_point(scene, ld: dict, where: str) -> None:
    """SceneError when a point force's point lies outside its block beyond ``scene.tolerance``."""
    block = scene.blocks[ld["_blocks"][0]]
    polys = block.pieces
    if inside(ld["point"], polys, scene.tolerance):
        return
    dist = min(point_to_hull(ld["point"], poly.vertices) for poly in polys)
    raise SceneError(f"{where}.point: {_vec(ld['point'])} lies outside block '{block.id}', {dist:.3g} m from it "
                     f"(the geometric tolerance is {scene.tolerance:.3g} m): a point force acts at a point of "
                     f"its block")


def check_live_work(scene) -> None:
    """SceneError when the live load does no work on any free block's unblocked dofs."""
    from limit.model import loads
    from limit.model.assemble import blocked_mask

    keep = blocked_mask(scene)
    if np.any(loads.assemble(scene, scene.live).ravel()[keep]):
        return
    if not scene.live:
        raise NoLiveWork("loads.live: no live load, so alpha multiplies nothing (add one, e.g. "
                         "{\"type\": \"body_force\", \"direction\": [1, 0" + (", 0" if scene.dim == 3 else "") + "]})")
    why = [f"loads.live[{k}] {_no_work(scene, ld, keep)}" for k, ld in enumerate(scene.live)]
    raise NoLiveWork("the live load does no work on any free block, so alpha multiplies nothing: " + "; ".join(why))


def _no_work(scene, ld: dict, keep) -> str:
    """Why one live load does no work (or that it does, cancelled by the others)."""
    from limit.model import loads

    t = ld["type"]
    vec = ld.get("direction") if t == "body_force" else ld.get("force") if t == "point_force" else None
    if vec is not None and not np.any(vec):
        return f"({t}) has a zero {'direction' if t == 'body_force' else 'force'}"
    if not any(not scene.blocks[i].fixed for i in ld["_blocks"]):
        on = ", ".join(f"'{scene.blocks[i].id}'" for i in ld["_blocks"][:5])
        return f"({t}) acts on fixed blocks only ({on})"
    if t == "pressure" and not np.any(loads.assemble(scene, [ld])):
        return (f"(pressure) loads no face: no face of its free blocks has the outward normal {_vec(ld['face'])} "
                "where the pressure is positive")
    if not np.any(loads.assemble(scene, [ld]).ravel()[keep]):
        return f"({t}) acts only along dofs its blocks have 'blocked'"
    return f"({t}) is cancelled by the others"


def _vec(v) -> str:
    return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"
