"""Checks that need the scene's interfaces (:func:`limit.geom.interfaces.find_interfaces`), run
where they are found (:func:`limit.model.assemble.assemble`, :func:`limit.results.info.scene_info`):

* an ``interfaces.friction`` entry for two blocks that share no interface;
* the gap (m) from a block that touches nothing to the nearest other block, for the messages
  that name it with the ``tolerance`` key that would close it.
"""
from __future__ import annotations

import numpy as np

from limit.errors import SceneError
from limit.model.hull_distance import pieces_distance


def check_friction_pairs(scene, I) -> None:
    """SceneError naming the first ``interfaces.friction`` entry whose blocks share no interface,
    or the first ``joints`` entry that selects no interface."""
    if scene.joint_groups:
        from limit.model.joint_groups import check_selected

        check_selected(scene, I)
    if not scene.friction_pairs:
        return
    touching = {(min(a, b), max(a, b)) for a, b in zip(np.asarray(I.a).tolist(), np.asarray(I.b).tolist())}
    ids = scene.block_index()
    for k, item in enumerate(scene.data.get("interfaces", {}).get("friction", [])):
        ia, ib = sorted(ids[x] for x in item["blocks"])
        if (ia, ib) in touching:
            continue
        a, b = scene.blocks[ia], scene.blocks[ib]
        where = f"interfaces.friction[{k}].blocks: '{a.id}' and '{b.id}'"
        if a.fixed and b.fixed:
            raise SceneError(f"{where} are both fixed: a joint between two supports is not modelled, so the "
                             f"override applies to nothing")
        gap = pieces_distance(a.pieces, b.pieces)
        if gap > scene.tolerance:
            raise SceneError(f"{where} do not touch ({gap:.3g} m apart, the geometric tolerance is "
                             f"{scene.tolerance:.3g} m): the override applies to no interface")
        raise SceneError(f"{where} meet only at a corner or an edge, with no contact of positive "
                         f"{'length' if scene.dim == 2 else 'area'}: the override applies to no interface")


def nearest_gap(scene, i: int) -> tuple[str | None, float]:
    """(id of the block nearest to block ``i``, their distance in m); (None, inf) alone."""
    lo = np.array([b.poly.vertices.min(axis=0) for b in scene.blocks])
    hi = np.array([b.poly.vertices.max(axis=0) for b in scene.blocks])
    box_gap = np.linalg.norm(np.maximum(0.0, np.maximum(lo - hi[i], lo[i] - hi)), axis=1)
    box_gap[i] = np.inf
    best, best_id = np.inf, None
    for j in np.argsort(box_gap):
        if box_gap[j] >= best:
            break
        d = pieces_distance(scene.blocks[i].pieces, scene.blocks[j].pieces)
        if d < best:
            best, best_id = d, scene.blocks[j].id
    return best_id, best


def gap_phrase(scene, i: int) -> str:
    """'the nearest block, 'b', is 0.002 m away, beyond the geometric tolerance 1e-06 m (the scene key
    "tolerance": 0.00201 would close the gap)' for block ``i``."""
    near, gap = nearest_gap(scene, i)
    if near is None:
        return "it is the only block"
    return (f"the nearest block, '{near}', is {gap:.3g} m away, beyond the geometric tolerance "
            f"{scene.tolerance:.3g} m (the scene key \"tolerance\": {_round_up(gap * 1.01)} would close the gap)")


def _round_up(x: float) -> str:
    """``x`` rounded up to 3 significant digits, as text."""
    if not x > 0:
        return f"{x:.3g}"
    e = int(np.floor(np.log10(x))) - 2
    return f"{np.ceil(x / 10.0 ** e) * 10.0 ** e:.3g}"
