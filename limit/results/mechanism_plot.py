"""``limit solve --plot OUT.png|DIR``: the mechanism figure of one result (:func:`reports.plots.mechanism_figure`),
the dead-load mechanism where the LP is "infeasible" (:mod:`limit.solve.dead_mechanism`); into a folder,
also the interactive view (:mod:`reports.view3d`) as ``<scene>-mechanism.html``, which opens offline."""
from __future__ import annotations

from pathlib import Path


def is_folder(path) -> bool:
    """A ``--plot`` target is a folder when it exists as one, ends with a separator or has no suffix."""
    p = str(path)
    return Path(p).is_dir() or p.endswith(("/", "\\")) or not Path(p).suffix


def plot_mechanism(scene, res: dict, path) -> list:
    """Write the figures of ``res`` (a public result) to ``path`` (a PNG file, or a folder: the PNG
    and the interactive page); returns the paths written (empty: nothing to draw)."""
    from reports.plots import mechanism_figure

    if not is_folder(path):
        return [Path(path)] if mechanism_figure(scene, res, None, path) else []
    folder = Path(path)
    folder.mkdir(parents=True, exist_ok=True)
    png = folder / f"{scene.name}-mechanism.png"
    if not mechanism_figure(scene, res, None, png):
        return []
    import datetime

    from reports import render, view3d

    page = folder / f"{scene.name}-mechanism.html"
    page.write_text(render.render("view.html", title=f"{scene.name}: collapse mechanism", wall_time=None,
                                  stamp=datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
                                  legend="Drag to turn, scroll to zoom; play animates the motion, the slider sets "
                                         "its amplitude; colour: the size of each block's motion.",
                                  **view3d.script(), views=view3d.divs(scene, res, {}, include_js=False)))
    return [png, page]
