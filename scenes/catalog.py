"""The scene catalog: every entry built by :mod:`scenes.builders` and kept as JSON
in ``scenes/catalog/``. ``python -m scenes.catalog`` rewrites the files;
``python -m scenes.catalog --check`` fails if a file differs from its builder.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from . import builders as B
from . import paper as PP
from .closed_forms import arch_reference

CATALOG_DIR = Path(__file__).resolve().parent / "catalog"

#: measured cost (CPU s) of each scene's YADE stage and LMGC90 stage on this project's 2-core
#: machine, for the validation to start the costliest stages first; written to meta.dem.cost_s
#: and meta.lmgc.cost_s (how they were measured: docs/performance.md, 'Catalog, benchmarks and
#: DEM stages').
DEM_COST_S = {"paper-fig2b-double-arch-2d": 689, "paper-fig3-opus-poligonale-70-2d": 426,
              "paper-fig6-intersecting-walls-3d": 309, "paper-fig5-trilithic-3d": 295,
              "paper-fig7-fountain-full-3d": 277, "paper-fig3-opus-poligonale-40-2d": 236, "corner-walls-3d": 119,
              "paper-fig7-fountain-half-3d": 108, "paper-fig4-opus-africanum-2d": 81, "wall-6x5-3d": 63,
              "wall-out-of-plane-3d": 62, "ferris-tinloi-wall-2d": 57, "paper-fig3-opus-poligonale-25-2d": 51,
              "arch-semicircular-27-2d": 19, "paper-fig2a-double-arch-2d": 18, "wall-4x4-tilting-2d": 14,
              "cross-vault-3d": 547, "wall-flemish-openings-2d": 501, "wall-tee-3d": 210, "wall-buttressed-3d": 209,
              "dome-8x2-3d": 94, "wall-corner-3d": 68, "barrel-vault-3d": 51}
LMGC_COST_S = {"paper-fig3-opus-poligonale-70-2d": 190.0, "paper-fig3-opus-poligonale-40-2d": 61.0,
               "paper-fig2b-double-arch-2d": 58.0, "ferris-tinloi-wall-2d": 43.0, "corner-walls-3d": 40.0,
               "wall-6x5-3d": 35.0, "paper-fig4-opus-africanum-2d": 28.0, "paper-fig6-intersecting-walls-3d": 28.0,
               "wall-out-of-plane-3d": 20.0, "paper-fig3-opus-poligonale-25-2d": 16.0,
               "paper-fig7-fountain-full-3d": 13.0, "arch-semicircular-27-2d": 11.0, "wall-4x4-tilting-2d": 11.0,
               "paper-fig5-trilithic-3d": 9.0, "wall-flemish-openings-2d": 357.0, "wall-tee-3d": 77.0,
               "wall-buttressed-3d": 77.0, "wall-corner-3d": 45.0, "cross-vault-3d": 39.0, "barrel-vault-3d": 19.0,
               "dome-8x2-3d": 12.0}


#: what the 70-stone wall's DEM stages show (docs/performance.md)
FIG3_70_DEM_NOTE = (
    " YADE's vertex model does not settle with the stiffness on this wall: its collapse depends on the loading "
    "path, and the stage's value can fall below step 2, where the result file and the report flag it as "
    "suspect. LMGC90's stage lies slightly below step 2 at its finest time step, an error of the time step "
    "(docs/performance.md, 'Dynamic results below step 2').")


#: the report's worked example of the code check (reports/verdict.py): an illustrative site with
#: ag = 0.2 g on soil C (S = 1.2), NTC 2018 spectrum shape, mechanisms at ground level, FC 1.35
EXAMPLE_DEMAND = {"ag_g": 0.2, "S": 1.2, "F0": 2.5, "TB": 0.15, "TC": 0.5, "TD": 2.4, "q": 2.0, "fc": 1.35}
#: the same ground motion from the site (NTC 2018 3.2.3.2.1: S, TB, TC, TD derived from Tc* and soil B)
SITE_DEMAND = {"ag_g": 0.2, "F0": 2.5, "Tc_star": 0.4, "soil": "B", "q": 2.0, "fc": 1.35}


#: the scenes whose expected alpha is a four-hinge mechanism search (scenes/closed_forms.py,
#: scenes/generators/reference.py), about a minute in all, most of it the 27-voussoir arch
FOUR_HINGE = ("arch-semicircular-9-2d", "arch-segmental-7-3d", "arch-semicircular-27-2d", "arch-pointed-6-on-piers-2d")


def stored_references() -> dict:
    """name -> the four-hinge alpha stored in its file (``expected.alpha``), for each of FOUR_HINGE."""
    return {name: json.loads((CATALOG_DIR / f"{name}.json").read_text())["expected"]["alpha"] for name in FOUR_HINGE}


def hinge_reference(name: str, search, references: dict | None = None) -> float:
    """The four-hinge alpha of scene ``name`` rounded to 1e-10: ``references[name]`` where given,
    else ``search()``."""
    if references is not None and name in references:
        return references[name]
    return round(search(), 10)


def entries(references: dict | None = None) -> dict:
    """name -> scene dict, in report order. ``references``: name -> four-hinge alpha, taken instead
    of running the search (:func:`stored_references`: the values the files hold)."""
    out = {}

    def add(d):
        assert d["name"] not in out, d["name"]
        d["order"] = len(out)  # report order, kept in the file so listing needs no builder run
        out[d["name"]] = d

    add(B.single_block(dim=2, b=0.3, h=1.0, mu=0.6, name="block-rocking-2d",
                       expected={"alpha": 0.3, "rtol": 1e-6, "source": "analytic: overturning about the toe, alpha = b/h"}))
    add(B.single_block(dim=3, b=0.3, h=1.0, t=0.5, mu=0.6, name="block-rocking-3d",
                       expected={"alpha": 0.3, "rtol": 1e-6, "source": "analytic: overturning about the toe, alpha = b/h"}))
    add(B.single_block(dim=2, b=1.0, h=0.5, mu=0.4, name="block-sliding-2d",
                       expected={"alpha": 0.4, "rtol": 1e-6, "source": "analytic: sliding, alpha = mu (b/h = 2 > mu)"}))
    add(B.single_block(dim=3, b=1.0, h=0.5, t=1.0, mu=0.4, name="block-sliding-3d",
                       expected={"alpha": 0.4, "rtol": 1e-6, "source": "analytic: sliding, alpha = mu (b/h = 2 > mu)"}))
    add(B.stack(3, dim=2, b=0.3, h=0.4, mu=0.8, name="stack-3-2d",
                expected={"alpha": 0.3 / 1.2, "rtol": 1e-6,
                          "source": "analytic: the whole stack overturns about the base toe, alpha = b / H"}))
    add(B.portal(dim=2, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, mu=0.8, name="portal-2d", demand=EXAMPLE_DEMAND,
                 expected={"alpha": 0.2, "rtol": 1e-6,
                           "source": "analytic: sway mechanism with the lintel translating, alpha = b / h of the columns"}))
    add(B.stack(3, dim=3, b=0.3, h=0.4, t=0.3, mu=0.8, name="stack-3-3d",
                expected={"alpha": 0.3 / 1.2, "rtol": 1e-6,
                          "source": "analytic: the whole stack overturns about the base edge, alpha = b / H"}))
    add(B.portal(dim=3, col_b=0.3, col_h=1.5, span=1.0, lintel_h=0.3, mu=0.8, name="portal-3d",
                 expected={"alpha": 0.2, "rtol": 1e-6,
                           "source": "analytic: sway mechanism with the lintel translating, alpha = b / h of the columns"}))
    oop = B.running_bond_wall(6, 4, dim=3, L=0.4, H=0.175, T=0.2, mu=0.8, name="wall-out-of-plane-3d",
                              expected={"alpha_lp": 0.2 / 1.05, "rtol": 1e-6,
                                        "source": "analytic: the wall overturns about its base edge, alpha = t / H "
                                                  "(the LP's; frictional states lie below it, see the notes)"})
    oop["loads"]["live"] = [{"type": "body_force", "direction": [0.0, 1.0, 0.0]}]
    oop["demand"] = dict(EXAMPLE_DEMAND)
    oop["symmetry"] = "mirror"  # about the vertical plane x = 1.2 m (checked by limit.verdict.symmetry)
    # the worst direction, step 2 in each direction: half the circle solved, by the symmetry
    oop["meta"] = {"sweep": {"step": 5, "frictional": True},
                   "notes": "The LP's mechanism (overturning about the base edge, t/H) has no sliding, and step 2 "
                            "from its own starts stays at t/H. It is a frictional collapse state but not the lowest: "
                            "step 2 at a quarter of the friction finds a state in which 4 joints slide (2 twisting) "
                            "at zero normal force while 5 rock, and from it (the setting friction_starts) step 2 "
                            "verifies 0.181726, 4.6 % lower, the best state the MILP of limit/solve/milp.py found "
                            "(limit solve --global --global-time-limit 400; its proven bound stayed at 0). Both "
                            "engines follow t/H: a monotonic pushover need not reach the lowest frictional "
                            "collapse state."}
    add(oop)
    th = math.radians(30.0)
    obl = B.single_block(dim=3, b=0.4, h=1.0, t=0.25, mu=2.0, name="block-oblique-3d",
                         expected={"alpha": _oblique(0.2, 0.125, 1.0, th), "rtol": 1e-6,
                                   "source": "analytic: least b_e / ((h/2) d.n_e) over the base edges, load at 30 deg"})
    obl["loads"]["live"] = [{"type": "body_force", "direction": [math.cos(th), math.sin(th), 0.0]}]
    add(obl)
    add(B.confined_block(dim=2, b=0.4, h=1.0, mu=0.5, name="confined-block-2d",
                         expected={"alpha": B.confined_block_alpha(0.4, 1.0, 0.5), "rtol": 1e-6,
                                   "source": "analytic (scenes/builders.confined_block_alpha): it slides on "
                                             "floor and ceiling, alpha = mu^2 h / b for b < mu h"},
                         meta={"title": "A block wedged between a floor and a ceiling",
                               "notes": "Sliding needs dilatancy in the associative LP, which the ceiling forbids: "
                                        "the LP is unbounded, and the frictional collapse load is finite. Step 2 "
                                        "starts from an equilibrium of the dead load alone. The ceiling's reaction "
                                        "is statically indeterminate (any N2 >= 0 carries the weight): YADE's "
                                        "compliant contacts build up only the N2 the moment needs and slide at the "
                                        "closed form; LMGC90's rigid contact solver settles on a larger N2 and slides "
                                        "later (0.784 would need N2 = 0.28 W where 0.125 W suffices)."}))
    add(B.side_by_side(dim=2, mu=0.5, name="side-by-side-2d",
                       expected={"alpha": B.side_by_side_alpha(mu=0.5), "alpha_lp": 7 / 17, "rtol": 1e-6,
                                 "source": "analytic (scenes/builders.side_by_side): frictional 23/61, associative 7/17"},
                       meta={"title": "A slender block pushing a squat one",
                             "notes": "Rocking and sliding combine: the associative LP must dilate where the squat "
                                      "block slides and overestimates alpha by 9 %."}))
    facade = B.running_bond_wall(3, 3, dim=2, L=0.4, H=0.4, mu=1.2, name="wall-3x3-opening-2d",
                            expected={"alpha": 5 / 14, "alpha_lp": 1.0, "rtol": 1e-4,
                                      "source": "by hand: c1-3 (0.2 x 0.4 m, centroid (1.1, 0.6)) and c2-2 (0.4 x 0.4 m, "
                                                "centroid (1.0, 1.0)) turn together about the toe (1.2, 0.4); per unit "
                                                "rotation their centroids move 0.2 and 0.6 m along +x and rise 0.1 and "
                                                "0.2 m: work against the dead load 0.08*0.1 + 0.16*0.2 = 0.04, work of "
                                                "the live load 0.08*0.2 + 0.16*0.6 = 0.112 (times rho g t), alpha = "
                                                "0.04/0.112 = 5/14 (tests/test_catalog.py); no mechanism is lower: "
                                                "global minimum by mixed-integer LP (limit/solve/milp.py); the issue's DEM "
                                                "probe found 0.357"},
                            meta={"title": "3 x 3 running-bond wall whose joints open while they slide",
                                  "notes": "The LP's dilatant mechanism needs alpha = 1.0; without dilatancy the end "
                                           "blocks rock about a toe while the joints above open and slide at zero "
                                           "normal force, at 5/14. With a joint sliding, its capacity curve "
                                           "comes from incremental limit analysis (the code check's nonlinear "
                                           "part)."})
    facade["demand"] = dict(SITE_DEMAND)
    add(facade)
    add(B.running_bond_wall(6, 5, dim=3, mu=0.65, name="wall-6x5-3d"))
    hinge_src = ("four-hinge mechanism method over all hinge sets (scenes/closed_forms.py, independent of limit/); "
                 "sliding does not govern at mu = 0.6")
    ref9 = hinge_reference("arch-semicircular-9-2d", lambda: arch_reference(9, 1.0, 0.15), references)
    add(B.arch(9, R=1.0, t=0.15, dim=2, mu=0.6, name="arch-semicircular-9-2d",
               expected={"alpha": ref9, "rtol": 1e-6, "source": hinge_src}))
    ref7 = hinge_reference("arch-segmental-7-3d", lambda: arch_reference(7, 1.5, 0.2, 120.0), references)
    add(B.arch(7, R=1.5, t=0.2, span_deg=120, dim=3, mu=0.6, name="arch-segmental-7-3d",
               expected={"alpha": ref7, "rtol": 1e-6,
                         "source": hinge_src + " (the 3D arch is the 2D one extruded, loaded in its plane)"}))
    add(B.corner_walls(courses=4, len_a=4, len_b=3, name="corner-walls-3d"))
    for d in paper_entries() + benchmark_entries(references):
        add(d)
    add(generated_arch_entry(references))
    for d in generator_entries():
        add(d)
    for d in feature_entries():
        add(d)
    add(thick_wall_entry())
    for stage, costs in (("dem", DEM_COST_S), ("lmgc", LMGC_COST_S)):
        for name, cost in costs.items():
            out[name].setdefault("meta", {}).setdefault(stage, {})["cost_s"] = float(cost)
    return out


def paper_entries() -> list:
    """The structures of Baggio & Trovalusci's Figs. 1-7 (scenes/paper.py)."""
    src = PP.PAPER
    out = []
    out.append(PP.fig1_block(name="paper-fig1-block-2d",
                             expected={"alpha": 0.5, "alpha_lp": 0.5, "rtol": 1e-6,
                                       "source": "analytic: sliding at alpha = mu; " + src + ", Fig. 1: the "
                                                 "frictional and the dilatant interface give the same alpha"},
                             meta={"title": "Fig. 1: a block sliding, with friction and with dilatancy",
                                   "figure": "Fig. 1", "source": src,
                                   "published": {"alpha": 0.5, "source": src + ", Fig. 1 and its text",
                                                 "note": "The paper states alpha = mu for both interfaces "
                                                         "(mu = 0.5 here): no geometry enters."}}))
    for tex, pub in (("a", None), ("b", 0.15)):
        meta = {"title": f"Fig. 2{tex}: double-level arches on piers, texture ({tex})", "figure": f"Fig. 2{tex}",
                "source": src,
                "notes": "Dead load: every stone's weight; live: an extra vertical charge on the arch stones "
                         "(see scenes/paper.fig2_double_arch for why). The paper's alpha = 1 + ours."}
        if tex == "a":
            meta["published"] = {"alpha": None, "source": src + ", Fig. 2a",
                                 "note": "Paper: this pier texture cannot carry the arches' full weight (alpha < 1 "
                                         "in its convention). Ours collapses under its own weight (LP infeasible): "
                                         "the same verdict."}
        else:
            meta["published"] = {"alpha": pub, "source": src + ", Fig. 2b-c (1.15 = the arches' weight + 15 %)",
                                 "note": "The paper's 1.15 is 1 + alpha here. Our dimensions are a reconstruction "
                                         "(pier width picked within 0.30-0.45 m to land near it), so agreement "
                                         "checks the behaviour (a fails, b carries a little more than its weight, "
                                         "LP and NLP close), not the paper's drawing."}
        out.append(PP.fig2_double_arch(tex, meta=meta))
    for n, seed in ((25, 1), (40, 2), (70, 3)):
        name = f"paper-fig3-opus-poligonale-{n}-2d"
        meta = {"title": f"Fig. 3: 'opus poligonale' wall, {n} polygonal stones", "figure": "Fig. 3", "source": src,
                "notes": "Random convex stones (Voronoi cells, 3:1 wider than high); the monolith's overturning "
                         "alpha = W/H = 0.8 bounds the answer from above.",
                "published": {"alpha": None, "source": src + ", Fig. 3",
                              "note": "The paper gives its values only in the figure; its text reports quasi-"
                                      "monolithic collapse with the LP answer acceptable (LP close to NLP)."}}
        if n == 70:
            meta["notes"] += FIG3_70_DEM_NOTE
        out.append(PP.fig3_opus_poligonale(n_stones=n, seed=seed, aspect=3.0, name=name, meta=meta))
    out.append(PP.fig4_opus_africanum(meta={
        "title": "Fig. 4: 'opus africanum' wall, 57 stones, 138 joints", "figure": "Fig. 4", "source": src,
        "published": {"alpha": 0.106, "kind": "NLP from an arbitrary start", "source": src + ", Fig. 4a and text",
                      "note": "The paper's only number in its text is the poor local solution from an arbitrary "
                              "start (0.106, interpenetrating stones); its LP and LP-started NLP values are in the "
                              "figure. Ours: LP and NLP from the LP start differ widely, as the paper says."}}))
    out.append(PP.fig5_trilithic(meta={
        "title": "Fig. 5: trilithic structure, 17 blocks, 26 joints", "figure": "Fig. 5", "source": src,
        "published": {"alpha": 0.086, "kind": "LP", "source": src + ", Fig. 5 and text (simplex, 261 unknowns)",
                      "note": "The column slenderness b/H = 0.3/3.5 was chosen so that the sway of the frame "
                              "(alpha = b/H = 0.0857) matches the paper's 0.086; our LP finds a slightly cheaper "
                              "mechanism (the architraves slide on the middle columns) 3 % lower."}}))
    out.append(PP.fig6_intersecting_walls(meta={
        "title": "Fig. 6: wall held by an intersecting panel, 25 blocks, 61 joints", "figure": "Fig. 6",
        "source": src, "sweep": {"step": 5, "frictional": True},  # step 2 in every direction (docs/performance.md)
        "published": {"alpha": None, "source": src + ", Fig. 6",
                      "note": "No alpha in the paper's text; it describes the wall rotating as a whole with the "
                              "stones at the corner turning about z."}}))
    for half in (True, False):
        nm = "paper-fig7-fountain-half-3d" if half else "paper-fig7-fountain-full-3d"
        out.append(PP.fig7_fountain(half=half, meta={
            "title": "Fig. 7: Fontana Maggiore upper basin, " + ("half model by symmetry (26 blocks, 50 joints)"
                                                                 if half else "full model (48 blocks, 96 joints)"),
            "figure": "Fig. 7", "source": src,
            "notes": "The half model's mirror-plane blocks have y, rx, rz blocked; the full and half models must "
                     "agree (LP within 0.2 %: the 4-face friction pyramid is not mirror-symmetric on the cut "
                     "contacts; NLP equal).",
            "published": {"alpha": None, "source": src + ", Fig. 7",
                          "note": "No alpha in the paper's text."}}))
    return out


def benchmark_entries(references: dict | None = None) -> list:
    """Benchmarks from other publications (values we could confirm, with their sources);
    ``references`` as :func:`entries`."""
    out = []
    ref27 = hinge_reference("arch-semicircular-27-2d", lambda: arch_reference(27, 1.0, 0.15), references)
    out.append(B.arch(27, R=1.0, t=0.15, dim=2, mu=0.6, name="arch-semicircular-27-2d",
                      expected={"alpha": ref27, "rtol": 1e-6,
                                "source": "four-hinge mechanism method over all hinge sets (scenes/closed_forms.py, "
                                          "independent of limit/); sliding does not govern at mu = 0.6; the "
                                          "issue's probe found 0.1453 for mu >= 0.6"},
                      meta={"title": "27-voussoir semicircular arch (Gilbert, Casapulla & Ahmed 2006), t/R = 0.15, "
                                     "horizontal body force",
                            "source": "Gilbert, Casapulla & Ahmed, Computers & Structures 84 (2006) 873-887",
                            "published": {"alpha": None, "source": "Gilbert et al. 2006",
                                          "note": "Gilbert et al. study this arch's minimum thickness against mu "
                                                  "under self weight; their values are in a figure we could not "
                                                  "read. Checked here against the four-hinge mechanism method."}}))
    ftl = B.running_bond_wall(6, 5, dim=2, L=0.4, H=0.175, mu=0.65, name="ferris-tinloi-wall-2d",
                              meta={"title": "Ferris & Tin-Loi (2001) wall: 6 courses, 5 blocks wide, 0.4 x 0.175 m, "
                                             "mu = 0.65",
                                    "source": "Ferris & Tin-Loi, Int. J. Mech. Sci. 43 (2001) 209-224",
                                    "published": {"alpha": None, "source": "Ferris & Tin-Loi 2001",
                                                  "note": "Their load factors could not be confirmed from a stored "
                                                          "text (only the abstract was reachable); a third-party "
                                                          "reproduction quotes 'around 0.64' for an associative "
                                                          "model, unconfirmed. Checked by the MILP/iterative LP "
                                                          "instead."}})
    out.append(ftl)
    tilt = B.running_bond_wall(4, 4, dim=2, L=0.4, H=0.2, mu=0.6, name="wall-4x4-tilting-2d",
                               meta={"title": "4 x 4 running-bond wall on a tilting table (tilt angle = atan alpha)",
                                     "notes": "A table tilted by theta loads the wall with g cos(theta) normal to it "
                                              "and g sin(theta) along it: the same as the self weight plus alpha = "
                                              "tan(theta) times a horizontal body force.",
                                     "published": {"alpha": None, "source": "Gilbert et al. 2006 / Casapulla",
                                                   "note": "No confirmed published value was found; compared "
                                                           "with the DEM and the MILP."}})
    out.append(tilt)
    return out


def feature_entries() -> list:
    """One scene per joint property and load beyond the paper's model, each with its closed form
    (their tests: tests/test_ties.py, test_pressure.py, test_cohesion.py, test_crushing.py). A 0.4 m
    wide, 1.0 m tall block in 2D (1 m thick, W = rho g 0.4 = 7,848 N) on a fixed base."""
    W = 2000.0 * 9.81 * 0.4
    out = []
    tied = B.single_block(dim=2, b=0.4, h=1.0, mu=0.9, name="block-tied-2d",
                          expected={"alpha": 0.4 + 2 * 1000.0 / W, "rtol": 1e-6,
                                    "source": "analytic: overturning about the toe against the tie at the top, "
                                              "alpha W h/2 = W b/2 + C h, alpha = b/h + 2 C / W"},
                          meta={"title": "A block held back by a tie rod at its top (capacity 1 kN)",
                                "notes": "The tie yields at its capacity as the block overturns. YADE carries it as "
                                         "a spring capped at the capacity; LMGC90 has no ties and skips."})
    tied["blocks"].append(B.box_block("post", [-0.4, 0.5], [0.2, 1.0], fixed=True))
    tied["ties"] = [{"id": "rod", "from": {"block": "block", "point": [0.0, 1.0]},
                     "to": {"block": "post", "point": [-0.3, 1.0]}, "capacity": 1000.0}]
    out.append(tied)
    out.append(B.single_block(dim=2, b=0.4, h=1.0, mu=0.9, name="block-water-2d",
                              live=[{"type": "pressure", "blocks": ["block"], "face": [-1.0, 0.0], "value": 0.0,
                                     "gradient": 9810.0, "level": 1.0}],
                              expected={"alpha": 3 * W * 0.4 / 9810.0, "rtol": 1e-6,
                                        "source": "analytic: water to the top, resultant gamma h^2 t / 2 at h/3; "
                                                  "alpha gamma h^3 t / 6 = W b / 2, alpha = 3 W b / (gamma h^3 t)"},
                              meta={"title": "A block pushed over by water to its top (alpha times the hydrostatic "
                                             "pressure)"}))
    glued = B.single_block(dim=2, b=1.0, h=0.5, mu=0.3, name="block-glued-2d",
                           expected={"alpha": 0.3 + 2000.0 / (2000.0 * 9.81 * 0.5), "rtol": 1e-6,
                                     "source": "analytic: Mohr-Coulomb sliding, alpha W = mu W + c A"},
                           meta={"title": "A squat block on a mortar joint with cohesion 2 kPa",
                                 "notes": "YADE's vertex model bonds the joint (its cohesion shared over the "
                                          "contacts' Coulomb caps); LMGC90's contacts are dry and it skips."})
    glued["joints"] = [{"between": {"blocks": ["base", "block"]}, "cohesion": 2000.0}]
    out.append(glued)
    fc = 10 * W / (4 * 0.4)
    crushed = B.single_block(dim=2, b=0.4, h=1.0, mu=0.9, name="block-crushing-2d",
                             expected={"alpha": (0.4 - W / fc) / 1.0, "rtol": 1e-6,
                                       "source": "analytic: the hinge moves in by W / (2 fc t), alpha = (b - W / "
                                                 "(fc t)) / h (fc = 10 W / (4 A): a node of the chords, where the "
                                                 "linearised domain is exact)"},
                             meta={"title": "A block whose toe crushes (fc = 49 kPa)",
                                   "notes": "Crushing has no rigid-block DEM: the dynamic check skips it."})
    crushed["joints"] = [{"between": {"blocks": ["base", "block"]}, "fc": fc}]
    out.append(crushed)
    out.append(ntc_pier_entry())
    return out


def thick_wall_entry() -> dict:
    """The 3 x 3 running-bond wall of wall-3x3-opening-2d built in 3D, 0.6 m thick (1.2 m high, mu
    1.2), live load along +x, swept every 15 degrees with step 2 in each direction: its frictional
    worst direction is not the LP's.

    In its plane (+-x) the LP's dilatant mechanism needs alpha = 1 and the frictional one 5/14, the
    2D scene's hand derivation (every block 0.6 m thick, so the same ratio of works). Out of its
    plane (+-y) the wall overturns about its base edge: alpha = (T / 2) / (H / 2) = 0.6 / 1.2 = 0.5
    for the LP, and step 2 there is at most that. So the LP's worst direction is +-y (0.5) and the
    frictional one +-x (5/14)."""
    d = B.running_bond_wall(3, 3, dim=3, L=0.4, H=0.4, T=0.6, mu=1.2, name="wall-3x3-3d",
                            expected={"alpha": 5 / 14, "alpha_lp": 1.0, "rtol": 1e-4,
                                      "source": "by hand, as wall-3x3-opening-2d in its plane (every block 0.6 m "
                                                "thick): c1-3 and c2-2 turn together about the toe (1.2, 0.4), "
                                                "alpha = 0.04 / 0.112 = 5/14; the LP's dilatant mechanism needs 1"})
    d["meta"] = {"title": "3 x 3 running-bond wall in 3D, 0.6 m thick: the frictional worst direction is not the LP's",
                 "sweep": {"step": 15, "frictional": True},
                 "notes": "The LP's worst direction is out of the plane (+-y: the wall overturns about its base "
                          "edge at T / H = 0.5), where in its plane the LP's dilatant mechanism needs 1.0. Step 2 "
                          "in its plane finds 5/14: two blocks turn about a toe while the joints above open and "
                          "slide at zero normal force. So the frictional worst direction is in the plane, and a "
                          "sweep of the LP alone points to the wrong one."}
    return d


def ntc_pier_entry() -> dict:
    """A masonry pier in its plane with crushing at its base, against the flexural capacity of NTC
    2018 section 7.8.2.2.1, eq. (7.8.2): Mu = (l^2 t sigma0 / 2)(1 - sigma0 / (0.85 fd)), sigma0 =
    N / (l t) (the same stress block, fc = 0.85 fd, as limit/model/yield_domain.py's crushing).

    Pier l = 1.2 m, t = 0.3 m, three 1.0 m courses (h = 3.0 m), 1,800 kg/m^3 (W = 19,070.64 N),
    mu 0.6, fd = 2.0 MPa on every bed joint; a floor load P on its top makes N = 122,400 N at
    the base, sigma0 = 340 kPa, sigma0 / (0.85 fd) = 0.2 (a node of the chords, where the
    linearised domain is exact). Mu = 73,440 x 0.8 = 58,752 N m. Live load 10 kN along +x at the
    top's centre: alpha = Mu / (10 kN x 3.0 m) = 1.9584. The joint above carries 116,043 N and
    2/3 of the moment (capacity 56,424 N m against 39,168 N m), and the base slides only at mu N
    = 73,440 N: rocking at the base governs."""
    fd, l, t, h = 2.0e6, 1.2, 0.3, 3.0
    W = 1800.0 * 9.81 * l * t * h
    N = 0.2 * 0.85 * fd * l * t
    sigma0 = N / (l * t)
    Mu = l * l * t * sigma0 / 2.0 * (1.0 - sigma0 / (0.85 * fd))
    d = B.stack(3, dim=2, b=l, h=1.0, mu=0.6, name="pier-crushing-ntc-2d", thickness=t, density=1800.0,
                dead=[{"type": "self_weight"},
                      {"type": "point_force", "block": "s2", "force": [0.0, -(N - W)], "point": [l / 2, h]}],
                live=[{"type": "point_force", "block": "s2", "force": [1.0e4, 0.0], "point": [l / 2, h]}],
                expected={"alpha": Mu / (1.0e4 * h), "rtol": 1e-6,
                          "source": "NTC 2018 section 7.8.2.2.1, eq. (7.8.2): Mu = (l^2 t sigma0 / 2)(1 - sigma0 / "
                                    "(0.85 fd)), with l 1.2 m, t 0.3 m, sigma0 340 kPa, fd 2 MPa"},
                meta={"title": "A masonry pier in its plane, crushing at its base (NTC 2018 eq. 7.8.2)",
                      "notes": "The code's in-plane flexural capacity of a pier is the rocking of its base joint "
                               "with a stress block 0.85 fd at the toe. Crushing has no rigid-block DEM: the "
                               "dynamic check skips it."})
    d["joints"] = [{"between": {"blocks": pair}, "fc": 0.85 * fd} for pair in (["base", "s0"], ["s0", "s1"], ["s1", "s2"])]
    return d


def generated_arch_entry(references: dict | None = None) -> dict:
    """A pointed arch on piers with skewbacks from scenes.generators (``limit build arch --kind pointed
    --n 6 --pier-courses 2``), its reference the four-hinge search over the whole chain, piers included
    (``references`` as :func:`entries`)."""
    from .generators import arch as gen_arch
    from .generators.reference import chain_hinge_alpha

    d = gen_arch("pointed", span=2.0, thickness=0.25, n=6, pier_height=1.5, pier_width=0.5, pier_courses=2, mu=0.8,
                 name="arch-pointed-6-on-piers-2d")
    chain = ["pier-right-0", "skewback-right"] + [f"v{k}" for k in range(6)] + ["skewback-left", "pier-left-0"]
    ref = hinge_reference(d["name"], lambda: chain_hinge_alpha(d, chain, "base", "base")["alpha"], references)
    d["expected"] = {"alpha": ref, "rtol": 1e-6,
                     "source": "four-hinge mechanism method over the chain base | pier course | skewback | 6 "
                               "voussoirs | skewback | pier course | base, hinges at either end of any four "
                               "joints (scenes/generators/reference.chain_hinge_alpha with scenes/closed_forms."
                               "arch_hinge_alpha, independent of limit/); sliding does not govern at mu = 0.8"}
    d["meta"]["notes"] = ("Built by scenes.generators.arch. The mechanism takes the piers with it: hinges at a "
                          "pier's base, in the ring and at the other pier's base.")
    return d


def generator_entries() -> list:
    """One scene from each generator of scenes.generators besides the arch (:func:`generated_arch_entry`):
    a 2D Flemish-bond wall with a lintel and a flat arch, a corner, a T-junction, a buttressed wall
    loaded across, a barrel vault, a cross vault and a dome, each as ``limit build`` makes it with the
    parameters given here, the 3D ones declaring the paper's 4 sliding faces like the rest of the
    catalog (``limit build`` leaves the solver's 24). They carry no closed form (the generators' own
    tests check volumes, interface counts and the closed forms that exist): the dynamic check is
    their reference."""
    from .generators import barrel_vault, buttressed_wall, cross_vault, dome, wall, wall_corner, wall_tee

    made = [
        (wall(length=3.2, height=1.8, bond="flemish", dim=2, unit=(0.4, 0.2, 0.2), mu=0.7,
              openings=[{"x": 0.6, "width": 0.6, "sill": 0.6, "height": 0.8},
                        {"x": 2.0, "width": 0.6, "sill": 0.4, "height": 0.8, "head": "arch"}],
              name="wall-flemish-openings-2d"),
         "Built by scenes.generators.wall: Flemish bond, a window under a lintel and one under a flat arch "
         "of five voussoirs, loaded in its plane."),
        (wall_corner(length=1.6, length_b=1.2, height=0.8, mu=0.6, name="wall-corner-3d"),
         "Built by scenes.generators.wall_corner: two running-bond walls meeting at a corner, alternate "
         "courses interlocking; the load along +x pushes wall B out of its plane."),
        (wall_tee(length=2.4, length_b=1.2, height=0.8, mu=0.6, name="wall-tee-3d"),
         "Built by scenes.generators.wall_tee: a stem wall bonded into the middle of a main wall in "
         "alternate courses; the load along +x pushes the stem out of its plane."),
        (buttressed_wall(length=2.4, height=1.2, buttresses=(1.0,), width=0.4, depth=0.4, mu=0.7,
                         name="wall-buttressed-3d"),
         "Built by scenes.generators.buttressed_wall: a running-bond wall with one buttress bonded into it "
         "in alternate courses, loaded across the wall towards its front (-y), away from the buttress.",
         (0.0, -1.0, 0.0)),
        (barrel_vault(span=2.0, thickness=0.2, n=7, rings=3, ring_width=0.3, mu=0.7, name="barrel-vault-3d"),
         "Built by scenes.generators.barrel_vault: three staggered rings of seven voussoirs between fixed "
         "abutments, loaded along the span."),
        (cross_vault(span=2.0, thickness=0.2, n=6, segments=2, mu=0.8, name="cross-vault-3d"),
         "Built by scenes.generators.cross_vault: four webs of six courses of two staggered blocks meeting "
         "on the groins, on four fixed corner piers, loaded along one barrel's axis. YADE's vertex model "
         "collapses about 3.5 % below step 2, converged in the contact stiffness, where LMGC90 (rigid contacts) meets step 2 "
         "and step 2 from YADE's collapse state finds nothing lower: YADE's result is flagged suspect low, "
         "its cause open (docs/performance.md, 'The generators' catalog scenes')."),
        (dome(span=3.0, thickness=0.2, meridians=8, rings=2, mu=0.8, name="dome-8x2-3d"),
         "Built by scenes.generators.dome: two rings of eight voussoirs and a cap on a fixed base, "
         "loaded horizontally."),
    ]
    for d, note, *live in made:  # live: a live-load direction other than the generator's +x
        d["meta"]["notes"] = note
        if live:
            d["loads"]["live"] = [{"type": "body_force", "direction": list(live[0])}]
        if d["dim"] == 3:  # the paper's 4 faces, like the rest of the catalog; the cone stage gives the
            d["interfaces"] = {**d.get("interfaces", {}), "sliding_faces": 4}  # 24 faces of limit build
    return [d for d, *_ in made]


def _oblique(half_x, half_y, h, theta):
    """Least b_e / ((h / 2) d . n_e) over the base edges of a box under a load at angle theta."""
    d = (math.cos(theta), math.sin(theta))
    cands = [dist / (h / 2 * dn) for dn, dist in ((d[0], half_x), (-d[0], half_x), (d[1], half_y), (-d[1], half_y))
             if dn > 1e-12]
    return min(cands)


def write(check: bool = False, references: dict | None = None) -> int:
    """Write the catalog's files from the builders, or with ``check`` only compare them (1 if any
    differs); ``references`` as :func:`entries`."""
    CATALOG_DIR.mkdir(exist_ok=True)
    wanted = {f"{name}.json": json.dumps(d, indent=1) + "\n" for name, d in entries(references).items()}
    stale = []
    for fname, text in wanted.items():
        p = CATALOG_DIR / fname
        if check:
            if not p.exists() or p.read_text() != text:
                stale.append(fname)
        else:
            p.write_text(text)
    extra = sorted(p.name for p in CATALOG_DIR.glob("*.json") if p.name not in wanted)
    if check and (stale or extra):
        print(f"catalog out of date: {', '.join(stale + extra)} (run: python -m scenes.catalog)", file=sys.stderr)
        return 1
    if not check:
        for name in extra:
            (CATALOG_DIR / name).unlink()
        print(f"wrote {len(wanted)} scenes to {CATALOG_DIR}")
    return 0


def catalog_files() -> list[Path]:
    """The catalog's JSON files in report order (files no builder knows go last)."""
    order = {}
    for p in CATALOG_DIR.glob("*.json"):
        try:
            order[p] = json.loads(p.read_text()).get("order", 10**6)
        except ValueError:
            order[p] = 10**6
    return sorted(order, key=lambda p: (order[p], p.name))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m scenes.catalog", description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="only check that the JSON files match the builders")
    return write(check=ap.parse_args(argv).check)


if __name__ == "__main__":
    sys.exit(main())
