"""All convex pieces' faces and vertices packed into padded numpy arrays.

A piece is a convex block, or one part of a compound block (``Block.pieces``). Piece i owns faces ``ptr[i]:ptr[i+1]`` of the flat face arrays. The padded
per-block arrays repeat a block's first face / vertex, which leaves maxima and
minima over faces or vertices unchanged, so vectorised tests can ignore padding.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class FaceTable:
    ptr: np.ndarray        # (n+1,) face offsets per block
    normal: np.ndarray     # (F, d) outward unit normals
    offset: np.ndarray     # (F,) plane offsets: normal . x = offset
    point: np.ndarray      # (F, d) centre of each face's vertices (a point on its plane)
    nvert: np.ndarray      # (F,) number of vertices of each face
    verts: np.ndarray      # (F, kmax, d) face polygons, padded with their last vertex
    block_normals: np.ndarray   # (n, Fmax, d) padded per block
    block_offsets: np.ndarray   # (n, Fmax) offsets relative to the block centre: normal . (x - centre)
    block_centre: np.ndarray    # (n, d) mean vertex of each block (reference point)
    block_verts: np.ndarray     # (n, Vmax, d) padded per block


def build(polys) -> FaceTable:
    """The table of the convex polytopes ``polys`` (geometry.Polytope), in their order."""
    n = len(polys)
    d = polys[0].vertices.shape[1]
    nf = np.array([len(p.faces) for p in polys])
    ptr = np.concatenate([[0], np.cumsum(nf)])
    normal = np.vstack([p.face_normals for p in polys])
    offset = np.concatenate([p.face_offsets for p in polys])
    faces = [f for p in polys for f in p.faces]
    nvert = np.array([len(f) for f in faces])
    kmax = int(nvert.max())
    if np.all(nvert == kmax):
        verts = np.array(faces)
    else:
        verts = np.empty((len(faces), kmax, d))
        for i, f in enumerate(faces):
            verts[i, : len(f)] = f
            verts[i, len(f):] = f[-1]
    point = np.array([f.mean(axis=0) for f in faces]) if not np.all(nvert == kmax) else verts.mean(axis=1)
    centre = np.array([p.vertices.mean(axis=0) for p in polys])
    fmax = int(nf.max())
    nv = np.array([len(p.vertices) for p in polys])
    vmax = int(nv.max())
    if np.all(nf == fmax) and np.all(nv == vmax):
        bn = np.array([p.face_normals for p in polys])
        bv = np.array([p.vertices for p in polys])
        fp = point.reshape(n, fmax, d)
        bo = np.einsum("nfd,nfd->nf", bn, fp - centre[:, None, :])
    else:
        bn = np.empty((n, fmax, d))
        bo = np.empty((n, fmax))
        bv = np.empty((n, vmax, d))
        for i, p in enumerate(polys):
            k = len(p.faces)
            bn[i, :k], bn[i, k:] = p.face_normals, p.face_normals[0]
            loc = np.einsum("fd,fd->f", p.face_normals, point[ptr[i]:ptr[i + 1]] - centre[i])
            bo[i, :k], bo[i, k:] = loc, loc[0]
            m = len(p.vertices)
            bv[i, :m], bv[i, m:] = p.vertices, p.vertices[0]
    return FaceTable(ptr, normal, offset, point, nvert, verts, bn, bo, centre, bv)
