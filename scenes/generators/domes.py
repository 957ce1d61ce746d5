"""A hemispherical dome of horizontal rings of voussoirs, on a fixed base.

3D, z up, the sphere's centre at the origin; lengths in metres. Every ring is cut by the same
meridian planes (aligned meridians), so a voussoir's bed faces, like its meridian faces, pass
through the sphere's centre and are exactly the faces of the voussoirs above and below; its
intrados and extrados are flat (isosceles trapezoids through four points of a sphere).
"""
from __future__ import annotations

import math

import numpy as np

from .. import builders as B
from ._common import count, finish, positive


def dome_point(r, lat, lon):
    """The point at radius r (m), latitude and longitude (rad)."""
    return [r * math.cos(lat) * math.cos(lon), r * math.cos(lat) * math.sin(lon), r * math.sin(lat)]


def dome(span=3.0, thickness=0.2, meridians=12, rings=4, oculus=False, mu=0.8, density=2000.0, name=None) -> dict:
    """A hemispherical dome of rings of voussoirs and a cap; returns a ``blockscene/1`` dict.

    span: intrados diameter at the springing (m).
    thickness: of the shell (m).
    meridians: voussoirs per ring (>= 3).
    rings: rings, equally spaced in latitude; the cap (or the oculus) spans one more ring's angle.
    oculus: leave the top open instead of a cap.
    mu: friction coefficient.
    density: kg/m^3.
    name: the scene's name.

    Blocks: 'ring{j}-{i}' (ring j from the springing, meridian slice i from +x counter-clockwise),
    tagged 'voussoir', 'ring', 'ring-{j}', 'meridian-{i}', ring 0 also 'springing'; the cap 'cap'
    tagged 'cap' and 'key'; the fixed base 'base' (top at height 0, the springing plane).
    Loads: self weight (dead), 1 g along +x (live).
    """
    params = dict(span=span, thickness=thickness, meridians=meridians, rings=rings, oculus=oculus, mu=mu,
                  density=density)
    s, t = positive("span", span), positive("thickness", thickness)
    nm = count("meridians", meridians, 3)
    nr = count("rings", rings)
    ri, re = s / 2, s / 2 + t
    lats = [j * (math.pi / 2) / (nr + 1) for j in range(nr + 1)]
    lons = [2 * math.pi * i / nm for i in range(nm + 1)]
    blocks = [B.base(3, -re - t, re + t, -re - t, re + t)]
    for j in range(nr):
        for i in range(nm):
            V = [dome_point(r, la, lo) for r in (ri, re) for la in lats[j:j + 2] for lo in lons[i:i + 2]]
            tags = ["voussoir", "ring", f"ring-{j}", f"meridian-{i}"] + (["springing"] if j == 0 else [])
            blocks.append(B.vertex_block(f"ring{j}-{i}", np.array(V), tags=tags))
    if not oculus:
        top = lats[-1]
        V = [dome_point(r, top, lo) for r in (ri, re) for lo in lons[:-1]] + [[0.0, 0.0, re]]
        blocks.append(B.vertex_block("cap", np.array(V), tags=["cap", "key"]))
    sc = B.scene(name or f"dome-{nr}x{nm}-3d", 3, blocks, friction=float(mu), density=float(density),
                 sliding_faces=None)
    return finish(sc, f"Dome of {nr} rings of {nm} voussoirs" + (" with an oculus" if oculus else " and a cap"),
                  params)
