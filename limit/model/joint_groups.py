"""Joint groups: the scene's ``joints`` list (docs/formats.md, 'Joint groups'), each entry
selecting the joints between two blocks (``{"between": {"blocks": [id, id]}}``), between any
block with one tag and any block with another (``{"between": {"tags": [tag, tag]}}``, the two
tags may be the same), or every joint that lies in a plane (``{"between": {"plane": {"point",
"normal"}}}``: each corner of the joint within the scene's ``tolerance`` of it, e.g. a damp-proof
course), and setting their properties.

Precedence: the scene's ``friction`` for every joint, then the ``interfaces.friction`` pairs,
then the ``joints`` entries in the order of the file, a later entry winning over an earlier
one. ``mu``, ``cohesion``, ``tensile_strength`` and ``fc`` (Pa; fc 0: no crushing) are modelled
(the yield domain of :mod:`limit.model.yield_domain`). An entry that selects no joint is rejected
(:func:`check_selected`), naming it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from limit.errors import SceneError

#: the modelled stresses of a joint group (Pa, finite and >= 0)
STRESSES = ("cohesion", "tensile_strength", "fc")


@dataclass(frozen=True)
class JointGroup:
    """One ``joints`` entry: ``where`` ("joints[k]"), the block indices of each side (a pair of
    index sets), ``mu``, ``cohesion`` and ``tensile_strength`` (Pa); None: the entry leaves that
    property as it is; ``fc`` 0: no crushing."""

    where: str
    side_a: frozenset
    side_b: frozenset
    text: str
    mu: float | None
    cohesion: float | None = None
    tensile_strength: float | None = None
    fc: float | None = None
    #: a plane selection: (point (d,) m, unit normal (d,), tolerance m), or None
    plane: tuple | None = None

    def selects(self, a: np.ndarray, b: np.ndarray, polygons=None) -> np.ndarray:
        """(m,) bool: the joints between blocks ``a[k]`` and ``b[k]`` (``polygons[k]`` their
        corners, (k, d) m, needed by a plane selection) that this entry selects."""
        if self.plane is not None:
            p0, n, tol = self.plane
            return np.array([bool(np.all(np.abs((np.asarray(q, dtype=float) - p0) @ n) <= tol))
                             for q in (polygons or [])], dtype=bool).reshape(len(a))
        ina = np.isin(a, list(self.side_a))
        inb = np.isin(b, list(self.side_b))
        ina_b = np.isin(a, list(self.side_b))
        inb_a = np.isin(b, list(self.side_a))
        return (ina & inb) | (ina_b & inb_a)


def parse_joint_groups(entries: list, ids: dict, blocks: list, dim: int = 3, tolerance: float = 0.0) -> tuple:
    """The ``joints`` entries as :class:`JointGroup` (``ids``: block id -> index); SceneError naming
    an unknown block or tag, a block paired with itself, a plane without a point or a nonzero
    normal of ``dim`` numbers, or a property that is not modelled."""
    out = []
    tags = {}
    for b in blocks:
        for t in b.tags:
            tags.setdefault(t, set()).add(b.index)
    for k, e in enumerate(entries):
        where = f"joints[{k}]"
        for key in STRESSES:
            v = e.get(key)
            if v is not None and not (isinstance(v, (int, float)) and not isinstance(v, bool)
                                      and math.isfinite(v) and v >= 0):
                raise SceneError(f"{where}.{key}: must be a stress >= 0 in Pa, got {v!r}")
        sel = e.get("between") or {}
        plane = None
        if "plane" in sel:
            pl = sel["plane"] if isinstance(sel["plane"], dict) else {}
            vec = {}
            for key in ("point", "normal"):
                v = pl.get(key)
                if not (isinstance(v, list) and len(v) == dim and all(
                        isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)):
                    raise SceneError(f"{where}.between.plane.{key}: {dim} finite numbers, got {v!r}")
                vec[key] = np.asarray(v, dtype=float)
            big = float(np.abs(vec["normal"]).max())
            if big == 0.0:
                raise SceneError(f"{where}.between.plane.normal: must not be zero")
            n = vec["normal"] / big  # no overflow in the norm of a huge normal
            plane = (vec["point"], n / float(np.linalg.norm(n)), float(tolerance))
            sa = sb = frozenset()
            text = f"the plane through {pl['point']} with normal {pl['normal']}"
        elif "blocks" in sel:
            pair = sel["blocks"]
            for j, x in enumerate(pair):
                if x not in ids:
                    raise SceneError(f"{where}.between.blocks[{j}]: unknown block id '{x}'")
            if pair[0] == pair[1]:
                raise SceneError(f"{where}.between.blocks: a block cannot touch itself ('{pair[0]}')")
            sa, sb = frozenset([ids[pair[0]]]), frozenset([ids[pair[1]]])
            text = f"blocks '{pair[0]}' and '{pair[1]}'"
        elif "tags" in sel:
            pair = sel["tags"]
            for j, t in enumerate(pair):
                if t not in tags:
                    raise SceneError(f"{where}.between.tags[{j}]: no block has the tag '{t}'")
            sa, sb = frozenset(tags[pair[0]]), frozenset(tags[pair[1]])
            text = f"blocks tagged '{pair[0]}' and '{pair[1]}'"
        else:
            raise SceneError(f"{where}.between: give \"blocks\": [id, id], \"tags\": [tag, tag] or "
                             "\"plane\": {\"point\", \"normal\"}")
        opt = lambda key: None if e.get(key) is None else float(e[key])
        out.append(JointGroup(where, sa, sb, text, opt("mu"), opt("cohesion"), opt("tensile_strength"), opt("fc"),
                              plane))
    return tuple(out)


def check_selected(scene, I) -> None:
    """SceneError naming the first ``joints`` entry that selects none of the interfaces ``I``."""
    a, b = np.asarray(I.a), np.asarray(I.b)
    for g in scene.joint_groups:
        if not g.selects(a, b, I.polygons).any():
            raise SceneError(f"{g.where}.between: selects no joint: no interface "
                             + (f"lies in {g.text} (within the tolerance {g.plane[2]:.3g} m)" if g.plane is not None
                                else f"between {g.text}"))
