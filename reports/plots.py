"""Figures of the report (matplotlib, Agg backend).

* :func:`mechanism_figure`: the collapse mechanisms of one scene side by side
  (associative LP, frictional NLP, DEM motion) drawn like the paper's figures:
  blocks in the displaced position, the motion amplified so the largest vertex
  displacement is AMPLIFY of the scene size, the original outlines dashed,
  supports dark; 2D joints that slide in red, joints that rock or open in blue.
  3D scenes as axonometric views.
* :func:`alpha_chart`: alpha per scene and method beside the reference.
* :func:`time_error`: run time against error per method.
* :func:`capacity_figure`: the pushover curves of one scene, alpha against
  the control displacement (the live load's work-conjugate displacement), one
  line per YADE contact stiffness and one for LMGC90's trials, beside the limit
  analysis's alpha.
* :func:`direction_polar`: alpha against the live load's horizontal direction (3D),
  with its minimum marked.
"""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from limit.model.dims import rigid_velocity  # noqa: E402
from dem_validation import engines  # noqa: E402

AMPLIFY = 0.08
COLORS = {"lp": "#4c72b0", "nlp": "#dd8452", "dem": "#55a868", "ref": "black", "global": "#8172b3",
          "dead": "#c44e52"}
LABELS = {"lp": "LP (associative)", "nlp": "NLP (frictional)", "dem": "DEM (YADE)",
          "dead": "collapse under the dead load alone"}


def _moved(scene, per_block: dict, scale: float):
    """{block index: [displaced vertices of each of its convex pieces]} for the free blocks (rigid
    motion x scale; a compound block's parts move together about its centroid)."""
    out = {}
    for i in scene.free:
        b = scene.blocks[i]
        m = per_block.get(b.id)
        if m is None:
            continue
        m = np.asarray(m, dtype=float) * scale
        out[i] = [p.vertices + rigid_velocity(m, p.vertices - b.centroid, scene.dim) for p in b.pieces]
    return out


def _outlines(blocks) -> list:
    """The vertex arrays of every convex piece of ``blocks``."""
    return [p.vertices for b in blocks for p in b.pieces]


def _all_moved(moved: dict) -> list:
    return [v for vs in moved.values() for v in vs]


def _scale(scene, per_block: dict) -> float:
    """Factor bringing the largest vertex motion to AMPLIFY x the size of the free part."""
    free = [scene.blocks[i] for i in scene.free]
    if not free or not per_block:
        return 0.0
    pts = np.vstack([b.poly.vertices for b in free])
    size = float(np.linalg.norm(np.ptp(pts, axis=0)))
    moved = _moved(scene, per_block, 1.0)
    disp = max((np.abs(v - p.vertices).max() for i in moved for v, p in zip(moved[i], scene.blocks[i].pieces)),
               default=0.0)
    return AMPLIFY * size / disp if disp > 0 else 0.0


def _panels(la: dict, dem: dict | None):
    out = []
    lp, nlp = la.get("lp") or {}, la.get("nlp") or {}
    dead = lp.get("dead_load_mechanism")
    if dead and dead.get("mechanism"):  # the LP is infeasible: nothing else to draw
        return [("dead", dead["mechanism"], None, dead.get("interfaces"))]
    if lp.get("mechanism"):
        out.append(("lp", lp["mechanism"], lp.get("alpha"), lp.get("interfaces")))
    if nlp.get("status") == "optimal" and nlp.get("mechanism"):
        out.append(("nlp", nlp["mechanism"], nlp.get("alpha"), nlp.get("interfaces")))
    if dem and dem.get("displacement"):
        out.append(("dem", dem["displacement"], dem.get("alpha"), None))
    return out


def mechanism_figure(scene, la: dict, dem: dict | None, path) -> bool:
    """Write the mechanism figure of one scene; False if there is no mechanism to draw."""
    panels = _panels(la, dem)
    if not panels:
        return False
    I = None
    if scene.dim == 2:
        from limit.geom.interfaces import find_interfaces

        I = find_interfaces(scene)
    n = len(panels)
    if scene.dim == 2:
        fig, axes = plt.subplots(1, n, figsize=(5.2 * n, 4.4), squeeze=False)
    else:
        fig = plt.figure(figsize=(5.2 * n, 4.8))
        axes = np.array([[fig.add_subplot(1, n, k + 1, projection="3d") for k in range(n)]])
    for ax, (kind, mech, alpha, ifaces) in zip(axes[0], panels):
        scale = _scale(scene, mech)
        moved = _moved(scene, mech, scale)
        title = f"{LABELS[kind]}: alpha = {alpha:.4g}" if alpha is not None else LABELS[kind]
        if scene.dim == 2:
            _draw2d(ax, scene, moved, COLORS[kind], I, ifaces)
        else:
            _draw3d(ax, scene, moved, COLORS[kind])
        ax.set_title(title, fontsize=10)
    fig.suptitle(f"{scene.name}: collapse mechanisms (motion amplified)", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def _draw2d(ax, scene, moved, color, I, ifaces):
    fixed = _outlines(b for b in scene.blocks if b.fixed)
    orig = _outlines(scene.blocks[i] for i in scene.free)
    ax.add_collection(PolyCollection(fixed, facecolors="#555555", edgecolors="#333333", linewidths=0.6))
    ax.add_collection(PolyCollection(orig, facecolors="none", edgecolors="#999999", linewidths=0.5,
                                     linestyles="dashed"))
    ax.add_collection(PolyCollection(_all_moved(moved), facecolors=color, alpha=0.35, edgecolors=color,
                                     linewidths=0.8))
    if I is not None and ifaces:
        segs = {k: [I.polygons[j] for j in ifaces.get(k, []) if j < len(I)] for k in ("slide", "rock", "open")}
        if segs["rock"] or segs["open"]:
            ax.add_collection(LineCollection(segs["rock"] + segs["open"], colors="#1f4e9c", linewidths=2.0,
                                             label="rocks / opens"))
        if segs["slide"]:
            ax.add_collection(LineCollection(segs["slide"], colors="#c0392b", linewidths=2.6, label="slides"))
        ax.legend(loc="upper right", fontsize=7, framealpha=0.8)
    pts = np.vstack([b.poly.vertices for b in scene.blocks] + _all_moved(moved))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.03 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.tick_params(labelsize=7)


def _draw3d(ax, scene, moved, color):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    def faces(poly, verts):
        # face polygons re-mapped onto the displaced vertices (nearest original vertex)
        out = []
        for f in poly.faces:
            idx = [int(np.argmin(np.linalg.norm(poly.vertices - p, axis=1))) for p in f]
            out.append(verts[idx])
        return out

    fixed_faces, moved_faces = [], []
    for b in scene.blocks:
        for k, p in enumerate(b.pieces):
            if b.fixed:
                fixed_faces += faces(p, p.vertices)
            elif b.index in moved:
                moved_faces += faces(p, moved[b.index][k])
    # Supports as light wireframes (opaque faces of a large base would hide the blocks).
    ax.add_collection3d(Poly3DCollection(fixed_faces, facecolors=(0.5, 0.5, 0.5, 0.08), edgecolors="#777777",
                                         linewidths=0.4))
    ax.add_collection3d(Poly3DCollection(moved_faces, facecolors=color, edgecolors="#222222", linewidths=0.3,
                                         alpha=0.75))
    pts = np.vstack([scene.blocks[i].poly.vertices for i in scene.free] + _all_moved(moved))
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-9 * (hi - lo).max())))
    ax.view_init(elev=22, azim=-58)
    ax.set_xlabel("x", fontsize=7)
    ax.set_ylabel("y", fontsize=7)
    ax.set_zlabel("z", fontsize=7)
    ax.tick_params(labelsize=6)


def alpha_chart(df, path) -> None:
    """alpha per scene: LP, frictional (NLP / MILP), DEM, the reference and a published
    value (hollow diamond; the paper's Fig. 2 value is 1 + alpha of our scene, see its notes)."""
    d = df.iloc[::-1].reset_index(drop=True)
    if "pub_alpha" not in d:
        d["pub_alpha"] = np.nan
    fig, ax = plt.subplots(figsize=(10.5, 0.32 * len(d) + 1.6))
    y = np.arange(len(d))
    for col, kind, marker, dy in (("lp_alpha", "lp", "o", -0.18), ("fric_alpha", "nlp", "s", -0.06),
                                  ("dem_alpha", "dem", "^", 0.06), ("ref_alpha", "ref", "*", 0.18)):
        vals = d[col].astype(float)
        lab = {"lp_alpha": "LP", "fric_alpha": "frictional (NLP / MILP)", "dem_alpha": "DEM",
               "ref_alpha": "reference"}[col]
        ax.scatter(vals, y + dy, marker=marker, color=COLORS[kind], s=40 if kind != "ref" else 80, label=lab,
                   zorder=3)
    ax.scatter(d["pub_alpha"].astype(float), y + 0.18, marker="D", facecolors="none", edgecolors="#c44e52", s=55,
               label="published", zorder=3)
    # a scene without any alpha says why at the left edge (infeasible: collapse under the dead load)
    for k, r in d.iterrows():
        if not any(np.isfinite(float(v)) for v in (r.lp_alpha, r.fric_alpha, r.dem_alpha) if v is not None):
            ax.annotate(f"LP {r.lp_status}", (0.01, k), xycoords=("axes fraction", "data"), fontsize=7,
                        color="#8a1c1c", va="center")
    bad = d[(d.lp_status == "failed") | (d.nlp_status == "failed") | (d.dem_status == "failed")]
    for k in bad.index:
        ax.axhspan(k - 0.45, k + 0.45, color="#f8d7da", zorder=0)
    ax.set_yticks(y)
    ax.set_yticklabels(d.name, fontsize=8)
    ax.set_xlabel("collapse load factor alpha")
    ax.set_xscale("log")
    ax.grid(True, axis="x", which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: it hid points
    ax.set_title("alpha per scene (failed stages shaded red)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def time_error(df, path) -> None:
    """Run time against the error from the reference, per method (log-log)."""
    fig, ax = plt.subplots(figsize=(6.5, 4.6))
    shown = 0
    for col_t, col_e, kind, lab in (("lp_time_s", "lp_err", "lp", "LP"), ("nlp_time_s", "nlp_err", "nlp", "NLP"),
                                    ("dem_time_s", "dem_err", "dem", "DEM")):
        t = df[col_t].astype(float)
        e = df[col_e].astype(float).abs()
        ok = np.isfinite(t) & np.isfinite(e) & (t > 0)
        ax.scatter(t[ok], np.maximum(e[ok], 1e-10), color=COLORS[kind], label=f"{lab} ({int(ok.sum())} scenes)")
        shown += int(ok.sum())
    if not shown:  # e.g. a run of scenes without a reference: log axes need a positive range
        ax.set_xlim(1e-2, 1e4)
        ax.set_ylim(1e-11, 1.0)
        ax.text(0.5, 0.5, "no scene here has a reference alpha", transform=ax.transAxes, ha="center", fontsize=9)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.axhline(1e-10, color="#bbbbbb", lw=0.8, ls=":")
    ax.set_xlabel("run time (s)")
    ax.set_ylabel("|alpha - reference| / reference (floor 1e-10)")
    ax.set_title("run time against error (scenes with a reference)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def capacity_points(dem: dict) -> dict:
    """{eps: (control (m), alpha) arrays} of the DEM's equilibria, in load order, and the
    collapse: {eps: alpha_hi} under the key "collapse"; from the ``history`` records (load
    steps ending stable; settling counts as alpha = 0)."""
    curves, collapse = {}, {}
    for h in dem.get("history") or []:
        eps = h.get("eps")
        if h.get("outcome") == "stable" and h.get("control") is not None and h.get("phase") != "re-stiffen":
            curves.setdefault(eps, []).append((float(h["control"]), float(h["alpha"])))
        elif h.get("outcome") == "collapse":
            collapse[eps] = min(collapse.get(eps, np.inf), float(h["alpha"]))
    out = {}
    for eps, pts in curves.items():
        pts = sorted(pts, key=lambda q: q[1])  # bisection visits alphas out of order: by load
        out[eps] = (np.array([q[0] for q in pts]), np.array([q[1] for q in pts]))
    return {"curves": out, "collapse": collapse}


def capacity_figure(dem: dict | None, la_alpha, path, title="", lmgc: dict | None = None,
                    kinematic: dict | None = None) -> bool:
    """alpha against the control displacement (mm) of every YADE run and of LMGC90's
    trials (rigid blocks: each trial starts from rest, so its points are the ends of the
    trials that held, at a few micrometres, and its x the lowest that collapsed); dashed
    lines at the limit analysis's alpha (frictional where it ran), at YADE's extrapolated
    alpha and at LMGC90's; and ``kinematic`` (:func:`limit.verdict.local_check.capacity_curve`: the
    joint equations of a rocking mechanism, incremental limit analysis where a joint slides): the
    limit analysis's mechanism followed at finite displacement, alpha against its work-conjugate
    displacement, on a panel of its own beside the engines' curves, with a note on why the two
    differ in displacement. False (no figure) when there is nothing to draw."""
    pts = capacity_points(dem or {})
    rigid = capacity_points(lmgc) if lmgc and engines.of_result(lmgc).rigid else {"curves": {}}
    if not pts["curves"] and not rigid["curves"] and not kinematic:
        return False
    dyn = bool(pts["curves"] or rigid["curves"])
    if kinematic and dyn:  # the dynamic curves live at millimetres, the mechanism's at its full travel
        fig, (ax, axk) = plt.subplots(1, 2, figsize=(10.0, 3.8))
    else:
        fig, ax = plt.subplots(figsize=(6.0, 3.8))
        axk = ax
    for k, (eps, (u, a)) in enumerate(sorted(pts["curves"].items(), key=lambda q: -q[0])):
        line, = ax.plot(1e3 * u, a, "o-", ms=3.5, lw=1.2, label=f"YADE equilibria, eps = {eps:.2g}")
        hi = pts["collapse"].get(eps)
        if hi is not None and np.isfinite(hi) and len(u):
            ax.plot([1e3 * u[-1]], [hi], "x", color=line.get_color(), ms=8, mew=2)
    for u, a in rigid["curves"].values():
        ax.plot(1e3 * u, a, "s-", color="0.35", ms=3.5, lw=1.0, label="LMGC90 trials that held (rigid)")
        hi = min(rigid["collapse"].values(), default=None)
        if hi is not None and np.isfinite(hi) and len(u):
            ax.plot([1e3 * u[-1]], [hi], "x", color="0.35", ms=8, mew=2)
    if kinematic:
        how = "incremental, a joint slides" if kinematic.get("method") == "incremental" else "rocking"
        axk.plot(1e3 * np.asarray(kinematic["d_work"]), kinematic["alpha"], "-", color=COLORS["nlp"], lw=1.6,
                 label=f"limit analysis at finite displacement ({how})")
        if axk is not ax:
            axk.set_xlabel("control displacement (mm): live-load work / |live load|")
            axk.set_title("the limit analysis's mechanism at finite displacement (capacity curve)", fontsize=9)
            fig.text(0.5, 0.01, "left: the engines' equilibria before collapse, at contact compliance (mm); right: rigid "
                     "blocks after collapse starts, alpha as the geometry changes (flat where a block slides on a "
                     "plane). Their peaks compare; their displacements do not (rigid limit analysis has no contact "
                     "stiffness).", ha="center", va="bottom",
                     fontsize=6.5, wrap=True)
            axk.grid(True, alpha=0.3)
            axk.legend(fontsize=7, loc="upper right")
    if la_alpha is not None and np.isfinite(la_alpha):
        ax.axhline(la_alpha, color=COLORS["nlp"], ls="--", lw=1.2, label=f"limit analysis {la_alpha:.4g}")
    if (dem or {}).get("alpha") is not None:
        ax.axhline(dem["alpha"], color=COLORS["dem"], ls=":", lw=1.2, label=f"YADE, rigid contacts {dem['alpha']:.4g}")
    lm_alpha = (lmgc or {}).get("alpha") if (lmgc or {}).get("status") == "collapsed" else None
    if lm_alpha is not None and np.isfinite(lm_alpha):
        ax.axhline(lm_alpha, color="0.35", ls="-.", lw=1.2, label=f"LMGC90, rigid blocks {lm_alpha:.4g}")
    ax.set_xlabel("control displacement (mm): live-load work / |live load|")
    ax.set_ylabel("load factor alpha")
    ax.set_title(("pushover curves" + (f": {title}" if title else "")) + " (x: first collapse)", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout(rect=(0, 0.07, 1, 1) if axk is not ax else None)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def direction_polar(out: dict, path, title="") -> None:
    """Polar plot of alpha(theta) from :func:`limit.direction_sweep.sweep` (theta from the
    scene's own live direction, counter-clockwise seen from above), the minimum marked. Where
    the sweep knows the global azimuth of theta = 0 (gravity along -z), the plot is turned to
    it: seen from above with +x to the right, and theta = 0 drawn along the scene's direction."""
    th = np.radians(np.asarray(out["theta"], dtype=float))
    a = np.asarray(out["alpha"], dtype=float)
    fig = plt.figure(figsize=(4.8, 4.8))
    ax = fig.add_subplot(projection="polar")
    from limit.direction_sweep import format_direction

    az0 = out.get("azimuth0")
    if az0 is not None:  # seen from above, +x to the right
        ax.set_theta_offset(np.radians(az0))
    ok = np.isfinite(a)
    ax.plot(np.append(th[ok], th[ok][:1]), np.append(a[ok], a[ok][:1]), "o-", ms=3, lw=1.2, color=COLORS["lp"],
            label="LP alpha")
    if out.get("min_theta") is not None:
        d = out.get("min_direction")
        where = "" if d is None else f" {format_direction(d)}"
        ax.plot([np.radians(out["min_theta"])], [out["min_alpha"]], "*", ms=14, color="crimson",
                label=f"minimum {out['min_alpha']:.4g} at {out['min_theta']:g} deg{where}")
        nlp = ((out.get("min_nlp") or {}).get("nlp") or {})
        if nlp.get("status") == "optimal" and nlp.get("alpha") is not None:
            ax.plot([np.radians(out["min_theta"])], [nlp["alpha"]], "D", ms=7, color=COLORS["nlp"],
                    label=f"frictional there {nlp['alpha']:.4g}")
    fa = np.asarray(out.get("alpha_frictional") or [np.nan] * len(a), dtype=float)
    fok = np.isfinite(fa)
    if fok.any():  # step 2 at every direction
        ax.plot(np.append(th[fok], th[fok][:1]), np.append(fa[fok], fa[fok][:1]), "s-", ms=3, lw=1.2,
                color=COLORS["nlp"], label="frictional alpha (step 2)")
        if out.get("min_theta_frictional") is not None:
            ax.plot([np.radians(out["min_theta_frictional"])], [out["min_alpha_frictional"]], "P", ms=13,
                    color="#2c7a2c", label=f"frictional minimum {out['min_alpha_frictional']:.4g} at "
                                           f"{out['min_theta_frictional']:g} deg")
    ax.set_rlim(0, 1.05 * float(np.nanmax(a)) if ok.any() else 1.0)
    ax.set_title(("worst load direction" + (f": {title}" if title else "")
                  + ("" if az0 is None else f"\nseen from above, +x to the right; theta from the live direction "
                     f"(azimuth {az0:g} deg)")), fontsize=8)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.1, -0.12))
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
