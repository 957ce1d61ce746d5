"""``limit solve --plot OUT.png``: the mechanism figure of one result (:func:`reports.plots.mechanism_figure`),
the dead-load mechanism where the LP is "infeasible" (:mod:`limit.solve.dead_mechanism`)."""
from __future__ import annotations


def plot_mechanism(scene, res: dict, path) -> bool:
    """Write the figure of ``res`` (a public result) to ``path``; False when there is nothing to draw."""
    from reports.plots import mechanism_figure

    return mechanism_figure(scene, res, None, path)
