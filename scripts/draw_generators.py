"""Draw the pictures of docs/generators.md: one PNG per generator under docs/img/gen-*.png.

    .venv/bin/python scripts/draw_generators.py [OUTDIR]

Blocks are coloured by their tags (fixed blocks dark grey); 2D scenes are drawn as polygons,
3D scenes as their faces in an axonometric view.
"""
from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from scipy.spatial import ConvexHull  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from scenes import generators as G  # noqa: E402

COLOURS = [("fixed", "#555555"), ("key", "#c0392b"), ("springing", "#e67e22"), ("skewback", "#8e6e53"),
           ("lintel", "#6d4c41"), ("arch", "#d35400"), ("groin", "#d9a441"), ("cap", "#c0392b"),
           ("buttress", "#7f8c8d"), ("branch", "#a3b18a"), ("header", "#b5651d"), ("back", "#d8b48a"),
           ("pier", "#b0a58f"), ("voussoir", "#e8c07d"), ("stretcher", "#deb887")]


OPENINGS = [{"x": 0.4, "width": 0.8, "sill": 0.4, "height": 0.6, "head": "lintel"},
            {"x": 2.0, "width": 0.8, "sill": 0.0, "height": 0.8, "head": "arch"},
            {"x": 3.6, "width": 0.8, "sill": 0.0, "height": 0.6, "head": "round"}]


def colour(block):
    if block.get("fixed"):
        return COLOURS[0][1]
    tags = set(block.get("tags", []))
    for tag, c in COLOURS[1:]:
        if tag in tags:
            return c
    return "#deb887"


def points(block):
    """The block's vertices (k, d) from its box or vertex list."""
    if "vertices" in block:
        return np.asarray(block["vertices"], float)
    c, s = np.asarray(block["box"]["center"]), np.asarray(block["box"]["size"])
    d = len(c)
    corners = np.array(np.meshgrid(*[[-0.5, 0.5]] * d, indexing="ij")).reshape(d, -1).T
    return c + corners * s


def faces(P):
    """The planar faces of the convex hull of P (3D), each a vertex loop."""
    hull = ConvexHull(P)
    out, seen = [], []
    for eq in hull.equations:
        if any(np.allclose(eq, s, atol=1e-7) for s in seen):
            continue
        seen.append(eq)
        on = P[np.abs(P @ eq[:3] + eq[3]) < 1e-7 * max(1.0, np.abs(P).max())]
        if len(on) < 3:
            continue
        c = on.mean(axis=0)
        u = on[np.argmax(np.linalg.norm(on - c, axis=1))] - c
        u /= np.linalg.norm(u)
        v = np.cross(eq[:3], u)
        ang = np.arctan2((on - c) @ v, (on - c) @ u)
        out.append(on[np.argsort(ang)])
    return out


def draw2d(ax, scene, title):
    for b in scene["blocks"]:
        P = points(b)
        c = P.mean(axis=0)
        P = P[np.argsort(np.arctan2(P[:, 1] - c[1], P[:, 0] - c[0]))]
        ax.add_patch(Polygon(P, closed=True, fc=colour(b), ec="k", lw=0.5))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(title, fontsize=9)


def draw3d(ax, scene, title, elev=22, azim=-60, skip_fixed=False):
    polys, cols = [], []
    allp = []
    for b in scene["blocks"]:
        if skip_fixed and b.get("fixed"):
            continue
        P = points(b)
        allp.append(P)
        for f in faces(P):
            polys.append(f)
            cols.append(colour(b))
    k = max(len(f) for f in polys)  # equal lengths (the last vertex repeated): ragged faces upset autoscaling
    polys = [np.vstack([f] + [f[-1:]] * (k - len(f))) for f in polys]
    ax.add_collection3d(Poly3DCollection(polys, facecolors=cols, edgecolors="k", linewidths=0.25))
    A = np.vstack(allp)
    lo, hi = A.min(axis=0), A.max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def save(fig, out, name):
    path = out / f"gen-{name}.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    print(f"{path}: {path.stat().st_size // 1024} KB")


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else Path(__file__).resolve().parents[1] / "docs" / "img"
    out.mkdir(parents=True, exist_ok=True)

    fig, axs = plt.subplots(1, 3, figsize=(9, 2.8))
    draw2d(axs[0], G.arch("semicircular", n=11), "semicircular, 11 voussoirs")
    draw2d(axs[1], G.arch("pointed", n=10), "pointed (equilateral), 10")
    draw2d(axs[2], G.arch("segmental", n=9, rise=0.5), "segmental, rise 0.5 m, 9")
    fig.tight_layout()
    save(fig, out, "arch")

    fig = plt.figure(figsize=(9, 4.6))
    grid = fig.add_gridspec(2, 3, height_ratios=[1, 1.2])
    for k, bond in enumerate(("running", "english", "flemish")):
        draw2d(fig.add_subplot(grid[0, k]), G.wall(length=2.4, height=1.2, bond=bond), f"{bond} bond")
    draw2d(fig.add_subplot(grid[1, :]), G.wall(length=4.8, height=1.6, openings=OPENINGS),
           "running bond with openings: lintel, flat arch, round arch")
    fig.tight_layout()
    save(fig, out, "wall-2d")

    fig = plt.figure(figsize=(8, 3.4))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    draw3d(ax, G.wall(length=2.4, height=1.2, bond="english", dim=3), "English bond, 3D", skip_fixed=True)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    draw3d(ax, G.wall(length=4.8, height=1.6, bond="flemish", dim=3, openings=OPENINGS),
           "Flemish bond, 3D, with openings", skip_fixed=True)
    fig.tight_layout()
    save(fig, out, "wall-3d")

    fig = plt.figure(figsize=(9, 3.2))
    for k, (sc, title) in enumerate(((G.wall_corner(), "corner"), (G.wall_tee(), "T-junction"),
                                     (G.buttressed_wall(), "buttresses"))):
        ax = fig.add_subplot(1, 3, k + 1, projection="3d")
        draw3d(ax, sc, title, elev=28, azim=-130, skip_fixed=True)
    fig.tight_layout()
    save(fig, out, "junctions")

    fig = plt.figure(figsize=(8, 3.2))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    draw3d(ax, G.barrel_vault(), "barrel vault, staggered rings", elev=20, azim=-60)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    draw3d(ax, G.cross_vault(), "cross vault on corner piers", elev=30, azim=-55)
    fig.tight_layout()
    save(fig, out, "vaults")

    fig = plt.figure(figsize=(8, 3.2))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    draw3d(ax, G.dome(), "dome, 4 rings of 12 and a cap", elev=20, azim=-60, skip_fixed=True)
    ax = fig.add_subplot(1, 2, 2, projection="3d")
    draw3d(ax, G.dome(oculus=True, meridians=16, rings=5), "dome with an oculus", elev=40, azim=-60,
           skip_fixed=True)
    fig.tight_layout()
    save(fig, out, "dome")


if __name__ == "__main__":
    main()
