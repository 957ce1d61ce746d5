"""Candidate tie positions for ``limit design``: wall to wall, at given levels.

Rule: at each level z (m along the scene's up direction, -gravity), every block of group A that
the horizontal plane z cuts is paired with every block of group B that it cuts, except a block
with itself and two fixed blocks. The tie runs between the two blocks' points at that level
straight above or below their centroids (the centroid moved along the up direction to z); a
block whose point so found lies outside it (a slanted or hollow block) is left out at that level.
The design's LP then chooses among the candidates (most get no capacity), so the rule may offer
many: a course of n_A and n_B blocks gives n_A n_B candidates per level.

Groups are the blocks that carry a tag (the generators tag walls ``main`` and ``branch``;
``scenes/generators/junctions.py``), or ``*`` for every block. Default levels: the mid-height of
the highest course of group A, that is the mid-height of the topmost block of A that the other
blocks of A do not rise above.
"""
from __future__ import annotations

import numpy as np

from limit.errors import SceneError


def _group(scene, tag: str) -> list:
    blocks = [b for b in scene.blocks if tag == "*" or tag in b.tags]
    if not blocks:
        known = sorted({t for b in scene.blocks for t in b.tags})
        raise SceneError(f"--wall-to-wall: no block carries the tag '{tag}' (tags in the scene: "
                         f"{', '.join(known[:12]) or 'none'}{' ...' if len(known) > 12 else ''})")
    return blocks


def _up(scene) -> np.ndarray:
    g = np.asarray(scene.gravity, dtype=float)
    n = float(np.linalg.norm(g))
    if n == 0.0:
        raise SceneError("--wall-to-wall: the scene has no gravity, so no level is horizontal")
    return -g / n


def default_levels(scene, tag_a: str) -> list[float]:
    """[z] (m): the mid-height of group A's highest course (the module docstring's rule)."""
    up = _up(scene)
    top = max(_group(scene, tag_a), key=lambda b: float(np.max(b.poly.vertices @ up)))
    h = top.poly.vertices @ up
    return [0.5 * float(h.min() + h.max())]


def wall_to_wall(data: dict, tag_a: str, tag_b: str, levels=None) -> list[dict]:
    """Candidate tie entries (the scene format's ``ties``, without ``capacity``; points in the
    scene file's units) between the blocks tagged ``tag_a`` and ``tag_b`` of the scene dict
    ``data`` at each of ``levels`` (in the file's units; None: :func:`default_levels`). ids
    ``w2w-{level}-{a}-{b}``. SceneError naming the tag or the level when nothing can be
    generated."""
    from limit.model.hull_distance import inside
    from limit.model.scene import load_scene
    from limit.model.units import DEFAULT, FACTORS

    scene = load_scene(data)
    k = FACTORS[data.get("units", DEFAULT)]  # metres per file unit
    up = _up(scene)
    A, B = _group(scene, tag_a), _group(scene, tag_b)
    zs = default_levels(scene, tag_a) if levels is None else [float(z) * k for z in levels]
    out = []
    for li, z in enumerate(zs):
        def cut(blocks):
            pts = {}
            for b in blocks:
                h = b.poly.vertices @ up
                if not h.min() < z < h.max():
                    continue
                c = b.centroid
                p = c + (z - float(c @ up)) * up
                if inside(p, b.pieces, scene.tolerance):
                    pts[b.id] = (b, p)
            return pts
        pa, pb = cut(A), cut(B)
        if not pa or not pb:
            which = tag_a if not pa else tag_b
            raise SceneError(f"--levels: the level {z / k:g} cuts no block tagged '{which}'")
        for ia, (ba, xa) in pa.items():
            for ib, (bb, xb) in pb.items():
                if ia == ib or (ba.fixed and bb.fixed):
                    continue
                out.append({"id": f"w2w-{li}-{ia}-{ib}",
                            "from": {"block": ia, "point": [float(v) / k for v in xa]},
                            "to": {"block": ib, "point": [float(v) / k for v in xb]}})
    if not out:
        raise SceneError(f"--wall-to-wall: no pair of distinct blocks tagged '{tag_a}' and '{tag_b}' at "
                         f"the levels {', '.join(f'{z / k:g}' for z in zs)}")
    return out
