"""Parametric generators of masonry structures, each returning a ``blockscene/1`` dict.

Every generator takes its dimensions in metres, puts the structure on a fixed base or fixed
supports, tags its blocks (pier, course-k, ring, springing, key, lintel, ...) so that loads and
joint properties can select them, and loads it with its self weight (dead) and a body force of
1 g along +x (live). 3D scenes leave the friction model to the solver (24 inscribed sliding faces
per interface). A bad parameter raises :class:`limit.errors.SceneError` (a ValueError) that
names it. docs/generators.md shows each one; ``limit build KIND ... -o SCENE.json`` writes them.
"""
from .arches import arch, arch_joints
from .domes import dome
from .junctions import buttressed_wall, wall_corner, wall_tee
from .vaults import barrel_vault, cross_vault
from .walls import wall

#: ``limit build`` KIND -> generator
GENERATORS = {"arch": arch, "wall": wall, "corner": wall_corner, "tee": wall_tee, "buttress": buttressed_wall,
              "barrel-vault": barrel_vault, "cross-vault": cross_vault, "dome": dome}

__all__ = ["GENERATORS", "arch", "arch_joints", "barrel_vault", "buttressed_wall", "cross_vault", "dome", "wall",
           "wall_corner", "wall_tee"]
