"""Reading a mechanism: per-block motions and what each interface does.

The interface strains ``q = B u`` (:mod:`limit.model.kinematics`) at the contact
centroid, in the local frame, give per interface (units of the mechanism's
displacement, m, for unit live-load work):

* ``slide``: tangential slip at the centroid, |q_t|;
* ``twist``: relative rotation about the normal times the contact's half
  size (l1 + l2), 3D only;
* ``rock``: relative rotation about in-plane axes times the contact's half
  size (the largest opening change across the contact);
* ``open``: normal separation at the centroid, q_n.

An interface does a thing when its measure exceeds ``ACTIVE`` times the largest
relative motion in the mechanism.
"""
from __future__ import annotations

import numpy as np

ACTIVE = 1e-5


def interface_motions(P, u) -> dict:
    """Per-interface motion measures (arrays of length m) of mechanism u."""
    I = P.I
    q = (P.B @ u).reshape(len(I), P.scene.ndof)
    if P.scene.dim == 2:
        slide = np.abs(q[:, 0])
        opening = q[:, 1]
        rock = np.abs(q[:, 2]) * I.l1
        twist = np.zeros(len(I))
    else:
        slide = np.hypot(q[:, 0], q[:, 1])
        opening = q[:, 2]
        rock = np.hypot(q[:, 3] * I.l2, q[:, 4] * I.l1)
        twist = np.abs(q[:, 5]) * (I.l1 + I.l2)
    return {"slide": slide, "twist": twist, "rock": rock, "open": opening}


def classify(P, u, active: float = ACTIVE) -> dict:
    """Boolean arrays (m,) of interfaces that slide, twist, rock or open in mechanism u."""
    mot = interface_motions(P, u)
    ref = max(float(np.max(np.abs(np.stack(list(mot.values()))))) if len(P.I) else 0.0, 1e-300)
    return {k: v > active * ref for k, v in mot.items()}


def per_block(P, u) -> dict:
    """{block id: [ux, uy, rz]} (2D) or [ux, uy, uz, rx, ry, rz] (3D) for the free blocks."""
    nd = P.scene.ndof
    U = P.full(u).reshape(-1, nd)
    return {P.scene.blocks[i].id: U[k].tolist() for k, i in enumerate(P.scene.free)}


def summary_lines(P, u, limit: int = 8) -> list[str]:
    """Human lines naming the interfaces that rock, slide, twist in the mechanism."""
    cls = classify(P, u)
    names = [f"{a}|{b}" for a, b in P.I.pairs(P.scene)]
    out = []
    for key, label in (("rock", "rock"), ("slide", "slide"), ("twist", "twist")):
        if P.scene.dim == 2 and key == "twist":
            continue
        idx = np.flatnonzero(cls[key])
        shown = ", ".join(names[i] for i in idx[:limit]) + (f", ... ({len(idx) - limit} more)" if len(idx) > limit else "")
        out.append(f"  {label:5s} {len(idx):4d} interface(s){': ' + shown if len(idx) else ''}")
    return out
