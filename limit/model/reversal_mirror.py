"""The mirror that maps a 3D scene onto itself with its live load reversed.

Take the vertical plane through the blocks' volume centroid c whose unit normal is the live
load's horizontal direction h (:func:`limit.model.loads.horizontal_direction`). The
reflection x -> c + M (x - c), M = I - 2 h h^T, maps the live direction to its reverse and leaves
gravity alone. Where it also maps every block onto a block of the same shape, fixity and density,
and every interface onto one of the same area and strength, a collapse state of the scene under
the reversed live load, reflected, is a collapse state of the scene itself at the same alpha:
equilibrium, yield and the flow rule are invariant under a reflection. A block's motion (u, w)
about its centroid (translation and rotation, 3D) reflects to (M u, -M w) on its image: the
rotation is a pseudovector (det M = -1).

A wall of blocks that run through its thickness is such a scene out of its plane, and an
assembly symmetric about the plane across its length is one in its plane. Only scenes whose loads
keep their meaning under the reflection qualify: live loads that are body forces (turned by
:mod:`limit.model.turned_load`), dead loads that are the self weight or body forces across h, and
no ties, pressure loads or blocked dofs.
"""
from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from limit.model.loads import horizontal_direction

#: centroids, corners and interface centroids match within this x the scene's size (m/m)
TOL = 1e-6


@dataclass(frozen=True)
class Mirror:
    """``image[i]``: the index of block i's mirror image; ``M`` (3, 3) the reflection's matrix."""

    image: np.ndarray
    M: np.ndarray

    def mechanism(self, scene, mech: dict) -> dict:
        """{block id: [ux, uy, uz, rx, ry, rz]} (per free block, about its centroid) of the
        reversed load's collapse state ``mech``, reflected onto the scene: block i's motion
        becomes its image's, (M u, -M w)."""
        out = {}
        index = {b.id: i for i, b in enumerate(scene.blocks)}
        for bid, v in mech.items():
            v = np.asarray(v, dtype=float)
            j = int(self.image[index[bid]])
            out[scene.blocks[j].id] = np.concatenate([self.M @ v[:3], -(self.M @ v[3:6])]).tolist()
        return out


def reflect(p: np.ndarray, c: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Points p (k, 3) mirrored about the plane through c (3,) with unit normal n (3,)."""
    return p - 2.0 * ((p - c) @ n)[:, None] * n


def same_shape(blocks, i: int, j: int, c: np.ndarray, n: np.ndarray, tol: float) -> bool:
    """Whether block i's corners, mirrored, are block j's (each within ``tol``, m)."""
    vi = reflect(np.asarray(blocks[i].poly.vertices, float), c, n)
    vj = np.asarray(blocks[j].poly.vertices, float)
    return len(vi) == len(vj) and bool(np.all(np.min(np.linalg.norm(vi[:, None] - vj[None], axis=2), axis=1) <= tol))


def _loads_qualify(scene, h: np.ndarray) -> bool:
    if scene.dim != 3 or scene.ties or any(b.blocked for b in scene.blocks):
        return False
    if not scene.live or any(ld.get("type") != "body_force" for ld in scene.live):
        return False
    for ld in scene.dead:
        if ld.get("type") == "self_weight":
            continue
        if ld.get("type") != "body_force" or abs(float(np.asarray(ld["direction"], float) @ h)) > TOL:
            return False
    return True


def _images(scene, c: np.ndarray, n: np.ndarray, tol: float) -> np.ndarray | None:
    """(n_blocks,) the index of every block's image, or None where one has none."""
    blocks = scene.blocks
    cen = np.array([b.centroid for b in blocks], dtype=float)
    vol = np.array([b.volume for b in blocks], dtype=float)
    key = [(b.fixed, b.density) for b in blocks]
    img = reflect(cen, c, n)
    out = np.full(len(blocks), -1)
    for i, near in enumerate(cKDTree(cen).query_ball_point(img, tol)):  # the centroids within tol of each image
        match = next((int(j) for j in sorted(near) if abs(vol[j] - vol[i]) <= TOL * vol[i] and key[j] == key[i]
                      and same_shape(blocks, i, int(j), c, n, tol)), None)
        if match is None:
            return None
        out[i] = match
    return out if len(set(out.tolist())) == len(blocks) else None


def _interfaces_match(I, image: np.ndarray, c: np.ndarray, n: np.ndarray, tol: float) -> bool:
    """Every interface's image (the images' pair, the reflected centroid) is an interface of the
    same area and strength."""
    props = [np.asarray(I.area, float), np.asarray(I.mu, float)] + \
        [np.asarray(p, float) for p in (I.cohesion, I.tensile, I.fc) if p is not None]
    pair = defaultdict(list)
    for k, (a, b) in enumerate(zip(I.a, I.b)):
        pair[(int(min(a, b)), int(max(a, b)))].append(k)
    img = reflect(np.asarray(I.centroid, float), c, n)
    for k, (a, b) in enumerate(zip(I.a, I.b)):
        ia, ib = int(image[a]), int(image[b])
        cands = pair.get((min(ia, ib), max(ia, ib)), [])
        if not any(np.linalg.norm(np.asarray(I.centroid[m], float) - img[k]) <= tol and
                   all(abs(p[m] - p[k]) <= TOL * max(abs(p[k]), 1e-300) or p[m] == p[k] for p in props)
                   for m in cands):
            return False
    return True


def find(scene, I) -> Mirror | None:
    """The reversal mirror of ``scene`` (with its interfaces ``I``), or None where the scene does
    not map onto itself (module docstring)."""
    try:
        h = np.asarray(horizontal_direction(scene), dtype=float)
    except ValueError:
        return None
    if not _loads_qualify(scene, h):
        return None
    vol = np.array([b.volume for b in scene.blocks], dtype=float)
    cen = np.array([b.centroid for b in scene.blocks], dtype=float)
    c = (vol[:, None] * cen).sum(0) / vol.sum()
    tol = TOL * (float(np.linalg.norm(np.ptp(cen, axis=0))) or 1.0)
    image = _images(scene, c, h, tol)
    if image is None or not _interfaces_match(I, image, c, h, tol):
        return None
    return Mirror(image=image, M=np.eye(3) - 2.0 * np.outer(h, h))
