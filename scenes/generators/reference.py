"""Reference collapse factors of generated 2D scenes, independent of :mod:`limit`.

:func:`chain_hinge_alpha`: a chain of blocks between fixed supports (an arch on piers: pier
courses, skewback, voussoirs, skewback, pier courses) by the four-hinge mechanism method of
:func:`scenes.closed_forms.arch_hinge_alpha`, with the joints found here from the block outlines
(collinear anti-parallel edges) and the weights and centroids by the shoelace formula.
"""
from __future__ import annotations

import numpy as np

from ..closed_forms import arch_hinge_alpha


def outline(block) -> np.ndarray:
    """The counter-clockwise outline (k, 2) of a 2D ``box`` or ``vertices`` block (m)."""
    if "box" in block:
        (cx, cy), (w, h) = block["box"]["center"], block["box"]["size"]
        return np.array([[cx - w / 2, cy - h / 2], [cx + w / 2, cy - h / 2],
                         [cx + w / 2, cy + h / 2], [cx - w / 2, cy + h / 2]])
    P = np.asarray(block["vertices"], float)
    c = P.mean(axis=0)
    return P[np.argsort(np.arctan2(P[:, 1] - c[1], P[:, 0] - c[0]))]


def shoelace(P):
    """Area (m^2) and centroid (m) of a counter-clockwise polygon."""
    x, y = P[:, 0], P[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    A = cr.sum() / 2
    return A, np.array([((x + xn) * cr).sum(), ((y + yn) * cr).sum()]) / (6 * A)


def shared_segment(P, Q, tol=1e-9):
    """The contact segment (2, 2) of two convex outlines: the overlap of an edge of P and an
    anti-parallel edge of Q on the same line; None if they share no length."""
    best = None
    for i in range(len(P)):
        a, b = P[i], P[(i + 1) % len(P)]
        d = (b - a) / np.linalg.norm(b - a)
        nrm = np.array([d[1], -d[0]])
        for j in range(len(Q)):
            c, e = Q[j], Q[(j + 1) % len(Q)]
            if abs((c - a) @ nrm) > tol or abs((e - a) @ nrm) > tol or (e - c) @ d >= 0:
                continue
            lo = max(0.0, (e - a) @ d)
            hi = min((b - a) @ d, (c - a) @ d)
            if hi - lo > tol and (best is None or hi - lo > best[0]):
                best = (hi - lo, np.array([a + lo * d, a + hi * d]))
    return None if best is None else best[1]


def chain_hinge_alpha(scene: dict, chain: list, support_start: str, support_end: str,
                      live_dir=(1.0, 0.0)) -> dict:
    """Least four-hinge collapse factor of the 2D blocks ``chain`` (ids, in order), the first
    resting on ``support_start`` and the last on ``support_end`` (fixed blocks; the same id
    for a common base). Dead load: the weights (area x density x g); live: the weights along
    ``live_dir``. Returns arch_hinge_alpha's dict (alpha, hinges, n_mechanisms)."""
    by_id = {b["id"]: b for b in scene["blocks"]}
    polys = [outline(by_id[i]) for i in [support_start] + list(chain) + [support_end]]
    joints = []
    for k in range(len(polys) - 1):
        seg = shared_segment(polys[k], polys[k + 1])
        if seg is None:
            raise ValueError(f"{([support_start] + list(chain))[k]} and the next block share no edge")
        joints.append(seg)
    rho = [by_id[i].get("density", scene.get("density", 2000.0)) for i in chain]
    A, C = zip(*(shoelace(P) for P in polys[1:-1]))
    return arch_hinge_alpha(np.array(joints), np.array(C), np.array(A) * np.array(rho), live_dir)
