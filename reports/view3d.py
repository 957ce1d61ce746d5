"""The report's interactive mechanism view: one plotly figure per motion (the limit analysis's
mechanism, each dynamic engine's displacement at collapse), offline (the page carries plotly's
script itself, see :func:`script`).

Each figure shows the blocks coloured by the size of their motion, the motion animated from rest
to full amplitude (play, pause, and a slider that sets the amplitude), the joints that hinge or
open, slide or twist in the limit analysis's mechanism as markers at their centroids, and the
live load on each free block as an arrow. A 2D scene is drawn in its plane (x, y) with the blocks
in :data:`BINS_2D` colour classes of motion.

The motion of a block is its rigid motion ``[u, r]`` (the result file's ``mechanism`` or
``displacement``, centroid velocity then rotation, :func:`limit.model.dims.rigid_velocity`)
scaled so that the largest vertex motion at full amplitude is :data:`AMPLIFY` times the size of
the structure: a mechanism is a velocity field, its size is arbitrary.
"""
from __future__ import annotations

import numpy as np

from limit.model.dims import rigid_velocity

#: the largest vertex motion at full amplitude, as a fraction of the structure's size
AMPLIFY = 0.08
#: animation frames from rest to full amplitude (each carries every moving corner: the page's
#: size grows with it; 6 frames of the 399-block free-form vault are 2.9 MB)
FRAMES = 6
#: colour classes of a 2D figure (one filled trace each)
BINS_2D = 6
#: live-load arrows are drawn on at most this many blocks (the largest forces)
MAX_ARROWS = 80
#: joint states drawn as markers, with their colours (the hinge marker covers 'open' too)
JOINT_STYLE = {"rock": ("hinges or opens", "#1f4e9c"), "slide": ("slides", "#c0392b"), "twist": ("twists", "#8e44ad")}
COLORSCALE = "Viridis"
#: a block whose largest vertex motion is below this fraction of the largest of all is drawn still
STILL = 1e-6


def _pieces(scene, which):
    """[(block, piece)] of the blocks ``which`` (indices)."""
    return [(scene.blocks[i], p) for i in which for p in scene.blocks[i].pieces]


def _size(scene) -> float:
    pts = np.vstack([b.poly.vertices for b in scene.blocks])
    return float(np.linalg.norm(np.ptp(pts, axis=0))) or 1.0


def _motion_field(scene, per_block: dict, pieces) -> tuple[list, float]:
    """([vertex motion (n, dim) per piece], scale) for unit amplitude; blocks absent from
    ``per_block`` do not move."""
    out = []
    for b, p in pieces:
        m = per_block.get(b.id)
        out.append(np.zeros_like(p.vertices) if m is None else
                   rigid_velocity(np.asarray(m, dtype=float), p.vertices - b.centroid, scene.dim))
    peak = max((float(np.abs(v).max()) for v in out if v.size), default=0.0)
    return out, (AMPLIFY * _size(scene) / peak if peak > 0 else 0.0)


def _triangles(piece) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3), triangles (m, 3)) of a convex polyhedron: each face fanned from its first
    corner, the corners mapped onto the piece's vertex list."""
    V = piece.vertices
    tri = []
    for f in piece.faces:
        idx = [int(np.argmin(np.linalg.norm(V - q, axis=1))) for q in f]
        tri += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return V, np.asarray(tri, dtype=int).reshape(-1, 3)


def _mesh(pieces, motions=None):
    """(vertices (n, 3), triangles (m, 3), vertex motion (n, 3)) of ``pieces`` concatenated
    (motion zero where ``motions`` is None)."""
    xs, tris, ds, off = [], [], [], 0
    for n, (_, p) in enumerate(pieces):
        V, T = _triangles(p)
        xs.append(V)
        tris.append(T + off)
        ds.append(motions[n] if motions is not None else np.zeros_like(V))
        off += len(V)
    if not xs:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=int), np.zeros((0, 3))
    return np.vstack(xs), np.vstack(tris), np.vstack(ds)


def _f32(a):
    """Coordinates for the page: single precision (plotly writes them as base64 typed arrays)."""
    return np.asarray(a, dtype=np.float32)


def _joints(scene, ifaces: dict | None, I=None) -> list[tuple[str, np.ndarray]]:
    """[(state, centroids (k, dim))] of the joints in each state of :data:`JOINT_STYLE`."""
    if not ifaces:
        return []
    from limit.geom.interfaces import find_interfaces

    I = find_interfaces(scene) if I is None else I
    out = []
    for state in JOINT_STYLE:
        idx = sorted(set(ifaces.get(state, [])) | (set(ifaces.get("open", [])) if state == "rock" else set()))
        pts = [np.asarray(I.polygons[j], dtype=float).mean(axis=0) for j in idx if j < len(I)]
        if pts:
            out.append((state, np.vstack(pts)))
    return out


def _loads(scene) -> tuple[np.ndarray, np.ndarray]:
    """(points (k, dim), vectors (k, dim)): the live force on each free block at its centroid,
    the largest :data:`MAX_ARROWS`, scaled so the longest is 0.12 x the structure's size."""
    from limit.model.loads import dead_and_live

    _, fL = dead_and_live(scene)
    F = np.asarray(fL, dtype=float)[:, : scene.dim]
    free = list(scene.free)
    C = np.vstack([scene.blocks[i].centroid for i in free]) if free else np.zeros((0, scene.dim))
    mag = np.linalg.norm(F, axis=1)
    keep = np.argsort(-mag)[:MAX_ARROWS]
    keep = keep[mag[keep] > 0]
    if not keep.size:
        return np.zeros((0, scene.dim)), np.zeros((0, scene.dim))
    return C[keep], F[keep] * (0.12 * _size(scene) / mag[keep].max())


def _controls(n_frames: int) -> dict:
    """Play / pause buttons and the amplitude slider of an animated figure."""
    steps = [{"method": "animate", "label": f"{k / (n_frames - 1):.1f}",
              "args": [[f"a{k}"], {"mode": "immediate", "frame": {"duration": 0, "redraw": True},
                                   "transition": {"duration": 0}}]} for k in range(n_frames)]
    play = {"frame": {"duration": 120, "redraw": True}, "fromcurrent": True, "transition": {"duration": 0}}
    return {"updatemenus": [{"type": "buttons", "showactive": False, "x": 0.0, "y": 0.0, "xanchor": "left",
                             "yanchor": "top", "direction": "left",
                             "buttons": [{"label": "play", "method": "animate", "args": [None, play]},
                                         {"label": "pause", "method": "animate",
                                          "args": [[None], {"mode": "immediate", "frame": {"duration": 0}}]}]}],
            "sliders": [{"active": n_frames - 1, "x": 0.18, "len": 0.8, "y": 0.0, "yanchor": "top",
                         "currentvalue": {"prefix": "amplitude "}, "steps": steps}]}


def figure(scene, per_block: dict, title: str, ifaces: dict | None = None, interfaces=None):
    """The animated figure of one motion (``per_block``: {block id: [u..., r...]}); ``ifaces``:
    the result's ``interfaces`` part (indices of the joints that rock, open, slide, twist) or None."""
    import plotly.graph_objects as go

    free = [int(i) for i in scene.free if per_block.get(scene.blocks[i].id) is not None]
    field, scale = _motion_field(scene, per_block, _pieces(scene, free))
    peak = max((float(np.abs(d).max()) for d in field if d.size), default=0.0)
    moves, k = set(), 0
    for i in free:  # a block whose vertices move less than STILL x the largest motion is drawn still
        n = len(scene.blocks[i].pieces)
        if any(float(np.abs(d).max()) > STILL * peak for d in field[k:k + n]):
            moves.add(i)
        k += n
    moving = [i for i in free if i in moves]
    pieces = _pieces(scene, moving)
    still = _pieces(scene, [b.index for b in scene.blocks if b.index not in moves])
    motions = [scale * d for d in _motion_field(scene, per_block, pieces)[0]]
    amps = np.linspace(0.0, 1.0, FRAMES)
    joints, (LP, LV) = _joints(scene, ifaces, interfaces), _loads(scene)
    if scene.dim == 3:
        data, frame_data = _traces3d(go, pieces, still, motions, amps, joints, LP, LV)
    else:
        data, frame_data = _traces2d(go, pieces, still, motions, amps, joints, LP, LV)
    data += _tie_traces(go, scene)
    frames = [go.Frame(name=f"a{k}", data=fd, traces=list(range(len(fd)))) for k, fd in enumerate(frame_data)]
    fig = go.Figure(data=data, frames=frames)
    fig.update_layout(title={"text": title, "font": {"size": 13}}, margin={"l": 0, "r": 0, "t": 40, "b": 60},
                      height=480, legend={"x": 0.0, "y": 1.0}, **_controls(FRAMES))
    if scene.dim == 3:
        fig.update_layout(scene={"aspectmode": "data", "xaxis_title": "x", "yaxis_title": "y", "zaxis_title": "z"})
    else:  # the whole motion in view (autorange follows the first frame only), at equal scales
        pts = [p.vertices for _, p in still] + [p.vertices + t * d for (_, p), d in zip(pieces, motions)
                                                for t in (0.0, 1.0)]
        P = np.vstack(pts) if pts else np.zeros((1, 2))
        lo, hi = P.min(axis=0), P.max(axis=0)
        pad = 0.05 * float((hi - lo).max() or 1.0)
        fig.update_layout(xaxis={"title": "x", "range": [lo[0] - pad, hi[0] + pad], "constrain": "domain"},
                          yaxis={"title": "y", "range": [lo[1] - pad, hi[1] + pad], "scaleanchor": "x",
                                 "constrain": "domain"},
                          plot_bgcolor="white", legend={"x": 1.02, "y": 1.0, "xanchor": "left"})
    return fig


def _tie_traces(go, scene) -> list:
    """The scene's tie rods (limit.model.ties) as one dashed line trace, drawn at rest."""
    ties = getattr(scene, "ties", ())
    if not ties:
        return []
    cols = [[], [], []]
    for t in ties:
        for k in range(scene.dim):
            cols[k] += [float(t.pa[k]), float(t.pb[k]), None]
    style = {"mode": "lines", "name": "tie rod" + ("s" if len(ties) > 1 else ""),
             "line": {"color": "#8e1b1b", "width": 4, "dash": "dash"}, "hoverinfo": "skip"}
    if scene.dim == 3:
        return [go.Scatter3d(x=cols[0], y=cols[1], z=cols[2], **style)]
    return [go.Scatter(x=cols[0], y=cols[1], **style)]


def _traces3d(go, pieces, still, motions, amps, joints, LP, LV):
    """(initial traces, per-frame traces): the moving mesh first, the only trace the frames update
    (its corners only: the triangles and colours stay)."""
    X, T, D = _mesh(pieces, motions)
    mag = np.linalg.norm(D, axis=1)
    Y = X + amps[-1] * D
    data = [go.Mesh3d(x=_f32(Y[:, 0]), y=_f32(Y[:, 1]), z=_f32(Y[:, 2]), i=T[:, 0], j=T[:, 1], k=T[:, 2],
                      intensity=_f32(mag), colorscale=COLORSCALE, cmin=0.0,
                      cmax=float(mag.max()) if mag.size else 1.0, colorbar={"title": "motion", "len": 0.6},
                      flatshading=True, name="blocks that move", showlegend=True, hoverinfo="skip")]
    Xs, Ts, _ = _mesh(still)
    data.append(go.Mesh3d(x=_f32(Xs[:, 0]), y=_f32(Xs[:, 1]), z=_f32(Xs[:, 2]), i=Ts[:, 0], j=Ts[:, 1], k=Ts[:, 2],
                          color="#aaaaaa", opacity=0.35, flatshading=True, name="fixed or still", showlegend=True,
                          hoverinfo="skip"))
    for state, P in joints:
        label, color = JOINT_STYLE[state]
        data.append(go.Scatter3d(x=_f32(P[:, 0]), y=_f32(P[:, 1]), z=_f32(P[:, 2]), mode="markers",
                                 name=f"joint {label}", marker={"size": 4, "color": color}))
    if len(LP):
        data.append(go.Cone(x=LP[:, 0], y=LP[:, 1], z=LP[:, 2], u=LV[:, 0], v=LV[:, 1], w=LV[:, 2],
                            anchor="tail", sizemode="absolute", sizeref=float(np.linalg.norm(LV, axis=1).max()) * 0.4,
                            colorscale=[[0, "#e67e22"], [1, "#e67e22"]], showscale=False, name="live load",
                            showlegend=True, hoverinfo="skip"))
    frames = []
    for t in amps:
        Y = X + t * D
        frames.append([go.Mesh3d(x=_f32(Y[:, 0]), y=_f32(Y[:, 1]), z=_f32(Y[:, 2]))])
    return data, frames


def _traces2d(go, pieces, still, motions, amps, joints, LP, LV):
    """(initial traces, per-frame traces) of a 2D figure: the moving blocks in BINS_2D traces by
    the size of their motion (the traces the frames update), then the still blocks, joints, loads."""
    import plotly.colors as pc

    size = np.array([float(np.linalg.norm(d, axis=1).max()) if d.size else 0.0 for d in motions])
    top = float(size.max()) if size.size else 0.0
    bins = np.minimum((size / top * BINS_2D).astype(int), BINS_2D - 1) if top > 0 else np.zeros(len(size), int)
    colors = pc.sample_colorscale(COLORSCALE, [(k + 0.5) / BINS_2D for k in range(BINS_2D)])

    def outline(V):
        V = np.vstack([V, V[:1]])
        return list(V[:, 0]) + [None], list(V[:, 1]) + [None]

    def moving(t):
        out = []
        for k in range(BINS_2D):
            xs, ys = [], []
            for n in np.flatnonzero(bins == k):
                x, y = outline(pieces[n][1].vertices + t * motions[n])
                xs += x
                ys += y
            lo, hi = k * top / BINS_2D, (k + 1) * top / BINS_2D
            out.append(go.Scatter(x=xs, y=ys, fill="toself", mode="lines", line={"color": "#333333", "width": 0.6},
                                  fillcolor=colors[k], name=f"motion {lo:.2g}-{hi:.2g}", hoverinfo="skip",
                                  showlegend=bool(xs)))
        return out

    xs, ys = [], []
    for _, p in still:
        x, y = outline(p.vertices)
        xs += x
        ys += y
    data = moving(amps[-1]) + [go.Scatter(x=xs, y=ys, fill="toself", mode="lines", fillcolor="#bbbbbb",
                                          line={"color": "#666666", "width": 0.6}, name="fixed or still",
                                          hoverinfo="skip")]
    for state, P in joints:
        label, color = JOINT_STYLE[state]
        data.append(go.Scatter(x=P[:, 0], y=P[:, 1], mode="markers", name=f"joint {label}",
                               marker={"size": 7, "color": color, "symbol": "diamond"}))
    if len(LP):
        ax, ay = [], []
        for p, v in zip(LP, LV):
            ax += [p[0], p[0] + v[0], None]
            ay += [p[1], p[1] + v[1], None]
        data.append(go.Scatter(x=ax, y=ay, mode="lines+markers", name="live load", line={"color": "#e67e22"},
                               marker={"symbol": "arrow", "angleref": "previous", "size": 9}))
    return data, [moving(t) for t in amps]


def motions(la: dict | None, engines: dict) -> list[tuple[str, dict, dict | None]]:
    """[(title, per-block motion, interfaces part)]: the limit analysis's mechanism (step 2's where
    it has one, else the LP's; the dead-load mechanism of an infeasible scene) and each engine's
    displacement at collapse (``engines``: {label: DEM result})."""
    la = la or {}
    out = []
    nlp, lp = la.get("nlp") or {}, la.get("lp") or {}
    dead = lp.get("dead_load_mechanism") or {}
    if nlp.get("mechanism") and nlp.get("status") == "optimal":
        out.append((f"limit analysis, frictional (step 2): alpha = {nlp['alpha']:.4g}", nlp["mechanism"],
                    nlp.get("interfaces") or lp.get("interfaces")))
    elif lp.get("mechanism"):
        a = lp.get("alpha")
        out.append(("limit analysis, associative LP" + (f": alpha = {a:.4g}" if a is not None else ""),
                    lp["mechanism"], lp.get("interfaces")))
    elif dead.get("mechanism"):
        out.append(("collapse under the dead load alone", dead["mechanism"], dead.get("interfaces")))
    for label, res in engines.items():
        res = res or {}
        if res.get("displacement"):
            a = res.get("alpha")
            out.append((f"{label} at collapse" + (f": alpha = {a:.4g}" if a is not None else ""),
                        res["displacement"], None))
    return out


def divs(scene, la: dict | None, engines: dict, include_js, interfaces=None) -> list[str]:
    """The HTML ``<div>``s of the figures of :func:`motions` (plotly's ``include_plotlyjs``:
    False where the page carries the script, see :func:`script`); ``interfaces``: the scene's,
    where the caller has them."""
    return [figure(scene, m, title, ifaces, interfaces).to_html(full_html=False, include_plotlyjs=include_js,
                                                    config={"displaylogo": False, "responsive": True},
                                                    auto_play=False)
            for title, m, ifaces in motions(la, engines)]


def script(path=None) -> dict:
    """plotly's script for the page template (``layout.html``): {"plotly_js": the script, to inline}
    with ``path`` None, else written to ``path`` once and {"plotly_src": its file name} (the catalog's
    pages share one copy)."""
    from plotly.offline import get_plotlyjs

    if path is None:
        return {"plotly_js": get_plotlyjs()}
    from pathlib import Path

    path = Path(path)
    if not path.exists():
        path.write_text(get_plotlyjs())
    return {"plotly_src": path.name}
