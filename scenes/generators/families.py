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


#: the kinds of :func:`dem_member`, in order: (name, dim). A family of len(DEM_KINDS) members meets
#: each once; a longer one repeats them with new draws.
DEM_KINDS = (("wall-openings-small-units", 2), ("wall-opening-large-units", 2), ("arch-on-piers", 2),
             ("buttressed-wall", 3), ("barrel-vault", 3), ("wall-opening-out-of-plane", 3),
             ("pointed-arch-on-piers", 2), ("wall-small-units", 3))
#: friction coefficients of the DEM family, drawn uniformly
DEM_MU = (0.5, 0.9)


def dem_member(seed: int, i: int) -> dict:
    """Member ``i`` of the DEM cross-check family of ``seed`` (issue: the dynamic check on
    structures it was not tuned on): kind DEM_KINDS[i % 8], 20 to 200 blocks, its parameters
    drawn from ``(seed, i)`` alone, recorded in ``meta.family``. Walls with openings and lintels
    with small units (courses of 50-60 mm) and large ones (0.2-0.3 m), arches on piers, a
    buttressed wall, a barrel vault, 2D and 3D; the 3D walls loaded out of their plane at 0 or 30
    degrees. No ``meta.dem`` knobs: the engines get their defaults, as a user's scene does."""
    from .arches import arch
    from .junctions import buttressed_wall
    from .vaults import barrel_vault

    rng = np.random.default_rng([seed, 1000 + i])
    kind, dim = DEM_KINDS[i % len(DEM_KINDS)]
    mu = round(float(rng.uniform(*DEM_MU)), 3)
    name = f"demfam-{seed}-{i}-{kind}"
    params: dict = {"kind": kind, "mu": mu}
    if kind in ("wall-openings-small-units", "wall-small-units"):
        H = round(float(rng.uniform(0.05, 0.06)), 4)
        L = round(H * float(rng.uniform(3.5, 4.5)), 4)
        nc = 14 if dim == 2 else 8
        length = round((8 if dim == 2 else 5) * L / (L / 2)) * (L / 2)
        ops = []
        if kind == "wall-openings-small-units":
            w = 1.5 * L
            ops = [{"x": 1.5 * L, "width": w, "sill": 4 * H, "height": 5 * H},
                   {"x": length - 1.5 * L - w, "width": w, "sill": 4 * H, "height": 5 * H}]
        sc = wall(length=length, height=nc * H, dim=dim, unit=(L, L / 2, H), openings=ops, mu=mu, name=name)
        params.update(unit=[L, L / 2, H], courses=nc, openings=len(ops))
    elif kind in ("wall-opening-large-units", "wall-opening-out-of-plane"):
        H = round(float(rng.uniform(0.2, 0.3)), 3)
        L = round(H * float(rng.uniform(1.5, 2.5)), 3)
        nc = 6
        length = 5 * L
        ops = [{"x": 2 * L, "width": L, "sill": 2 * H, "height": 2 * H}]
        sc = wall(length=length, height=nc * H, dim=dim, unit=(L, L / 2, H), openings=ops, mu=mu, name=name)
        params.update(unit=[L, L / 2, H], courses=nc, openings=1)
        if dim == 3:
            th = math.radians(ANGLES_3D[(i // len(DEM_KINDS)) % len(ANGLES_3D)])
            sc["loads"]["live"] = [{"type": "body_force", "direction": [math.sin(th), math.cos(th), 0.0]}]
            params["angle_from_normal_deg"] = math.degrees(th)
    elif kind in ("arch-on-piers", "pointed-arch-on-piers"):
        pointed = kind.startswith("pointed")
        n = int(rng.choice([8, 10, 12])) if pointed else int(rng.choice([7, 9, 11, 13]))
        span = round(float(rng.uniform(1.5, 3.0)), 2)
        t = round(span * float(rng.uniform(0.08, 0.14)), 3)
        sc = arch("pointed" if pointed else "semicircular", span=span, thickness=t, n=n, pier_height=1.0,
                  pier_width=round(max(0.4, 2.2 * t), 3), pier_courses=5, mu=mu, name=name)
        params.update(span=span, thickness=t, voussoirs=n)
    elif kind == "buttressed-wall":
        H = 0.2
        sc = buttressed_wall(length=2.4, height=6 * H, buttresses=(1.0,), width=0.4, depth=0.4,
                             unit=(0.4, 0.2, H), mu=mu, name=name)
        sc["loads"]["live"] = [{"type": "body_force", "direction": [0.0, -1.0, 0.0]}]
        params.update(length=2.4, courses=6)
    else:  # barrel vault
        n = int(rng.choice([7, 9]))
        sc = barrel_vault(span=round(float(rng.uniform(1.5, 2.5)), 2), thickness=0.2, n=n, rings=3,
                          ring_width=0.3, mu=mu, name=name)
        params.update(voussoirs=n, rings=3)
    sc.setdefault("meta", {})["family"] = {"seed": seed, "index": i, "dim": dim, **params}
    return sc


def dem_family(seed: int = 0, count: int = len(DEM_KINDS)) -> list[dict]:
    """``count`` members of the DEM cross-check family (:func:`dem_member`)."""
    return [dem_member(seed, i) for i in range(count)]
