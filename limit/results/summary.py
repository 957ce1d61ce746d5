"""The short human summary printed by ``python -m limit solve``, made from the result file's
content alone (a fresh result and a cached one print the same)."""
from __future__ import annotations

from limit.results.result_parts import ties_line
from limit.solve.status import GlobalStatus, Status


def _alpha(part: dict) -> str:
    a = part.get("alpha")
    return f"alpha = {a:.6g}" if a is not None else "alpha = -"


def format_result(res: dict) -> str:
    lines = [f"{res['scene']}: {res['dim']}D, {res['n_free_blocks']} free blocks, "
             f"{res['n_interfaces']} interfaces"]
    lp = res["lp"]
    model = lp["model"]
    cone = (f", {model['n_slide']}-face {model['slide_fit']} friction cone"
            if res["dim"] == 3 and model.get("n_slide") else "")
    lines.append(f"LP  ({lp['solver']}, {model['interfaces']} interfaces{cone}): {_alpha(lp)}  "
                 f"[{lp['status']}, {lp['time_s']:.3g} s]" + (f"  {lp['reason']}" if lp.get("reason") else ""))
    if lp["status"] == Status.OPTIMAL and (lp.get("interfaces") or {}).get("pairs"):
        lines.append("  mechanism (associative):")
        lines += ["  " + s for s in _joint_lines(lp["interfaces"], res["dim"])]
    if lp.get("ties"):
        lines.append(ties_line(lp["ties"]))
    nlp = res.get("nlp")
    if nlp:
        lines.append(f"NLP ({nlp.get('solver', '-')}): {_alpha(nlp)}  [{nlp['status']}, {nlp.get('time_s', 0):.3g} s]"
                     + (f"  {nlp['reason']}" if nlp.get("reason") else ""))
        if (nlp.get("interfaces") or {}).get("pairs"):  # step 2's own point (limit.step2._point_part)
            lines.append("  mechanism (frictional):")
            lines += ["  " + s for s in _joint_lines(nlp["interfaces"], res["dim"])]
            if nlp.get("ties"):
                lines.append(ties_line(nlp["ties"]))
        if nlp.get("alpha_arbitrary_start") is not None or nlp.get("arbitrary_start_status"):
            a = nlp.get("alpha_arbitrary_start")
            lines.append(f"  from an arbitrary start: {'alpha = %.6g' % a if a is not None else nlp['arbitrary_start_status']}")
        g = nlp.get("global")
        if g:
            a = g.get("alpha")
            lines.append(f"global minimum (MILP): {'alpha = %.6g' % a if a is not None else '-'}  [{g['status']}, "
                         f"{g.get('time_s') or 0:.3g} s]" + (f"  gap of the NLP {g['gap']:.2e}" if g.get("gap") is not None else "")
                         + {True: "  (its point passed the check: the answer)",
                            False: "  (its point failed the check: not the answer)"}.get(g.get("adopted"), ""))
            span = global_interval(nlp)
            if span is not None:
                lines.append(f"  not proven within the time limit: the frictional minimum lies in "
                             f"[{span[0]:.6g}, {span[1]:.6g}] (the MILP's bound, the answer)")
        ds = nlp.get("dem_start")
        if ds:
            a = ds.get("alpha")
            lines.append(f"from the {ds['source']} collapse state: {'alpha = %.6g' % a if a is not None else '-'}  "
                         f"[{ds['status']}, {ds.get('time_s') or 0:.3g} s]"
                         + ("  (the answer)" if ds.get("adopted") else f"  {ds['reason']}" if ds.get("reason") else ""))
        it = nlp.get("iterative_lp")
        if it:
            a = it.get("alpha")
            lines.append(f"iterative LP (Gilbert et al. 2006): {'alpha = %.6g' % a if a is not None else '-'}  "
                         f"[{it['status']}, {it.get('iterations')} LPs]")
    lb = res.get("lower_bound")
    if lb:
        lines.append(bound_line(lb, nlp))
    return "\n".join(lines)


def global_interval(nlp: dict | None) -> tuple[float, float] | None:
    """(lower, upper): the interval that holds the frictional minimum when the global MILP stopped
    at its time limit without a proof (``nlp.global.status`` "time_limit"): its proven bound
    (clipped at 0, as alpha >= 0 in the MILP) and step 2's verified answer. None where the MILP
    proved its optimum, has no bound, or step 2 has no verified alpha."""
    g = (nlp or {}).get("global") or {}
    bound, alpha = g.get("bound"), (nlp or {}).get("alpha")
    if g.get("status") != GlobalStatus.TIME_LIMIT or bound is None or alpha is None or nlp.get("status") != Status.OPTIMAL:
        return None
    try:
        lo = max(float(bound), 0.0)
    except (TypeError, ValueError):
        return None
    return (lo, float(alpha)) if lo == lo and lo <= alpha else None


def bound_line(lb: dict, nlp: dict | None) -> str:
    """The lower bound's line (:mod:`limit.solve.radenkovic`), with the interval it gives the
    frictional minimum when step 2 has a verified alpha."""
    a = lb.get("alpha")
    line = (f"lower bound (Radenkovic, friction removed, cohesion kept): "
            f"{'alpha = %.6g' % a if a is not None else '-'}  [{lb['status']}, {lb.get('time_s') or 0:.3g} s]")
    if a is None:
        return line + (f"  {lb['reason']}" if lb.get("reason") else "")
    if nlp and nlp.get("status") == Status.OPTIMAL and nlp.get("alpha") is not None:
        line += f"\n  the frictional minimum lies in [{a:.6g}, {nlp['alpha']:.6g}]"
    return line


def _joint_lines(ifaces: dict, dim: int, limit: int = 8) -> list[str]:
    """The lines of :func:`limit.solve.mechanism.summary_lines` from a result file's ``interfaces``
    part (the joint indices that rock, slide, twist, and the block pairs)."""
    names = [f"{a}|{b}" for a, b in ifaces["pairs"]]
    out = []
    for key in ("rock", "slide", "twist"):
        if dim == 2 and key == "twist":
            continue
        idx = list(ifaces.get(key) or [])
        shown = ", ".join(names[i] for i in idx[:limit]) + (f", ... ({len(idx) - limit} more)" if len(idx) > limit else "")
        out.append(f"  {key:5s} {len(idx):4d} interface(s){': ' + shown if idx else ''}")
    return out
