"""Tie rods: the scene's ``ties`` list (docs/formats.md, 'Ties'), tension-only members between a
point of one block and a point of another (possibly fixed) block.

A tie carries a tension T with 0 <= T <= capacity (N) along the line through its two points: it
pulls its ``from`` block towards its ``to`` block and the ``to`` block back, and resists no
shear, bending or compression. Rigid-plastic like the joints: it does not stretch until T reaches
its capacity, and then yields at that force; it goes slack when its ends approach. The limit
analysis sees it as one more static unknown T with two yield rows, ``-T <= 0`` and ``T <=
capacity`` (associative: yielding dissipates capacity times the elongation; going slack,
nothing), and its elongation rate e . (v_to(p_to) - v_from(p_from)) as the conjugate strain
(e: the unit vector from ``from`` to ``to``).

``prestress`` (N, at most the capacity) is recorded with the tie. It does not change either
step's answer: both search every statically admissible state, so any tension in [0, capacity]
is open to them whatever the tie's initial force.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from limit.errors import SceneError


@dataclass(frozen=True)
class Tie:
    """One ``ties`` entry: ``where`` ("ties[k]"), its ``id``, the block indices and points (m)
    of its two ends, ``capacity`` and ``prestress`` (N)."""

    where: str
    id: str
    a: int
    pa: np.ndarray
    b: int
    pb: np.ndarray
    capacity: float
    prestress: float = 0.0

    @property
    def direction(self) -> np.ndarray:
        """Unit vector from the ``from`` point to the ``to`` point."""
        d = self.pb - self.pa
        return d / np.linalg.norm(d)

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.pb - self.pa))


def _number(v, where: str, positive: bool) -> float:
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and (v > 0 if positive else v >= 0)
    if not ok:
        raise SceneError(f"{where}: must be a force {'> 0' if positive else '>= 0'} in N, got {v!r}")
    return float(v)


def parse_ties(entries: list, ids: dict, blocks: list, dim: int, tolerance: float) -> tuple:
    """The ``ties`` entries as :class:`Tie` (``ids``: block id -> index); SceneError naming the
    entry and key: an unknown block, a point of the wrong length or outside its block (beyond
    ``tolerance``, m), two ends at one point or on one block, two fixed ends, a capacity that is
    not a positive force, a prestress above the capacity, a repeated id."""
    from limit.model.hull_distance import inside, point_to_hull

    out, seen = [], set()
    for k, e in enumerate(entries):
        where = f"ties[{k}]"
        tid = str(e.get("id", f"tie-{k}"))
        if tid in seen:
            raise SceneError(f"{where}.id: '{tid}' names another tie too")
        seen.add(tid)
        ends = []
        for side in ("from", "to"):
            end = e.get(side)
            if not isinstance(end, dict) or "block" not in end or "point" not in end:
                raise SceneError(f"{where}.{side}: give {{\"block\": id, \"point\": [{', '.join('xyz'[:dim])}]}}")
            if end["block"] not in ids:
                raise SceneError(f"{where}.{side}.block: unknown block id '{end['block']}'")
            p = end["point"]
            if not (isinstance(p, list) and len(p) == dim and all(isinstance(x, (int, float)) and
                                                                  not isinstance(x, bool) and math.isfinite(x)
                                                                  for x in p)):
                raise SceneError(f"{where}.{side}.point: {dim} finite coordinates (m), got {p!r}")
            i = ids[end["block"]]
            p = np.asarray(p, dtype=float)
            if not inside(p, blocks[i].pieces, tolerance):
                dist = min(point_to_hull(p, poly.vertices) for poly in blocks[i].pieces)
                raise SceneError(f"{where}.{side}.point: lies outside block '{end['block']}', {dist:.3g} m from it "
                                 f"(the geometric tolerance is {tolerance:.3g} m): a tie is anchored in its block")
            ends.append((i, p))
        (a, pa), (b, pb) = ends
        if a == b:
            raise SceneError(f"{where}: both ends are in block '{blocks[a].id}' (a tie joins two blocks)")
        if np.linalg.norm(pb - pa) <= tolerance:
            raise SceneError(f"{where}: its two points coincide (a tie needs a length)")
        if blocks[a].fixed and blocks[b].fixed:
            raise SceneError(f"{where}: both ends are fixed blocks ('{blocks[a].id}', '{blocks[b].id}'): it holds nothing")
        cap = _number(e.get("capacity"), f"{where}.capacity", positive=True)
        pre = _number(e.get("prestress", 0.0), f"{where}.prestress", positive=False)
        if pre > cap:
            raise SceneError(f"{where}.prestress: {pre:g} N is above its capacity {cap:g} N")
        out.append(Tie(where, tid, a, pa, b, pb, cap, pre))
    return tuple(out)


def generalised_forces(scene, ties) -> np.ndarray:
    """(n_free * ndof, n_ties): the generalised forces on the free blocks (loads.py's layout: force
    and moment about each centroid) of a unit tension in each tie: +e at its ``from`` point,
    -e at its ``to`` point."""
    from limit.model.loads import _cross, free_index

    d, nd = scene.dim, scene.ndof
    fi = free_index(scene)
    out = np.zeros((len(scene.free) * nd, len(ties)))
    for j, t in enumerate(ties):
        e = t.direction
        for i, p, f in ((t.a, t.pa, e), (t.b, t.pb, -e)):
            if fi[i] < 0:
                continue
            c = scene.blocks[i].centroid
            out[fi[i] * nd:fi[i] * nd + d, j] = f
            out[fi[i] * nd + d:(fi[i] + 1) * nd, j] = _cross(d, p - c, f)
    return out
