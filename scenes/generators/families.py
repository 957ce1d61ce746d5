"""Seeded families of generated scenes: corpora for benchmarks and tests that are not the
catalog's own structures.

:func:`wall_family` draws walls from :func:`scenes.generators.walls.wall` over the ranges an
engineer meets: 2D and 3D, friction coefficients 0.5 to 1.2, unit aspect ratios (length over
course height) 1.5 to 4, running, English and Flemish bond, with and without openings, and in 3D
a horizontal load at 0 or 30 degrees from the wall's plane. Each member is a function of
``(seed, index)`` alone, so a member can be rebuilt without the others.
"""
from __future__ import annotations

import math

import numpy as np

from .walls import wall

#: Member i is in 2D for even i, in 3D for odd i; with j = i // 2 it has the friction
#: coefficient MUS[(j + 3 (i % 2)) % 6], the bond BONDS[j % 3], openings when (j // 3) is odd and
#: in 3D the load angle ANGLES_3D[j % 2]: twelve members meet every friction value in both
#: dimensions and every bond with and without openings.
MUS = (0.5, 0.6, 0.7, 0.8, 0.9, 1.2)
BONDS = ("running", "english", "flemish")
#: the unit's length over the course height, drawn uniformly
ASPECT = (1.5, 4.0)
#: the course height (m), drawn uniformly
COURSE_H = (0.06, 0.2)
#: the wall's length over its height, drawn uniformly
PROPORTION = (1.0, 3.0)
#: 3D load directions, degrees from +x (the wall's plane) toward +y (out of it)
ANGLES_3D = (0.0, 30.0)


def member(seed: int, i: int, blocks: int) -> dict:
    """Family member ``i`` of ``seed`` with about ``blocks`` blocks (within about 20 %): a
    ``blockscene/1`` dict whose ``meta.family`` records its parameters."""
    rng = np.random.default_rng([seed, i])
    dim, j = 2 + i % 2, i // 2
    mu = MUS[(j + 3 * (i % 2)) % len(MUS)]
    bond = BONDS[j % len(BONDS)]
    openings = (j // 3) % 2 == 1
    H = float(rng.uniform(*COURSE_H))
    aspect = float(rng.uniform(*ASPECT))
    prop = float(rng.uniform(*PROPORTION))
    L = aspect * H
    W = L / 2
    angle = ANGLES_3D[j % len(ANGLES_3D)] if dim == 3 else 0.0
    # blocks per unit area of elevation, measured on a small patch of the same bond (headers
    # and two-wythe courses make English and Flemish bond denser than running bond)
    probe = wall(length=8 * L, height=8 * H, bond=bond, dim=dim, unit=(L, W, H), mu=mu)
    density = (len(probe["blocks"]) - 1) / (64 * L * H)
    height = math.sqrt(blocks / density / prop)
    nc = max(4, round(height / H))
    length = max(4 * L, round(prop * nc * H / (L / 2)) * (L / 2))
    ops = []
    if openings:
        nc = max(nc, 8)
        sill, oh = round(0.25 * nc) * H, max(2, round(0.35 * nc)) * H
        w = max(L, round(0.18 * length / (L / 2)) * (L / 2))
        for x in (0.2 * length, 0.8 * length - w):
            ops.append({"x": round(x / (L / 2)) * (L / 2), "width": w, "sill": sill, "height": oh})
    name = f"family-{seed}-{i}-{dim}d-{bond}-mu{mu:g}" + ("-openings" if ops else "")
    sc = wall(length=length, height=nc * H, bond=bond, dim=dim, unit=(L, W, H), openings=ops, mu=mu, name=name)
    if dim == 3:
        th = math.radians(angle)
        sc["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    sc.setdefault("meta", {})["family"] = {
        "seed": seed, "index": i, "dim": dim, "mu": mu, "bond": bond, "aspect": aspect, "course_h": H,
        "openings": len(ops), "angle_deg": angle, "target_blocks": blocks}
    return sc


def wall_family(seed: int = 0, count: int = 12, blocks=(100, 3000)) -> list[dict]:
    """``count`` members of the wall family: member i (:func:`member`) has about
    ``blocks[0] (blocks[1] / blocks[0]) ** (i / (count - 1))`` blocks (evenly spaced on a log
    scale), so that sizes, dimensions, friction values and bonds all mix."""
    lo, hi = blocks
    sizes = [lo] if count == 1 else [lo * (hi / lo) ** (k / (count - 1)) for k in range(count)]
    return [member(seed, i, int(round(n))) for i, n in enumerate(sizes)]
