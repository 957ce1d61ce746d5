"""The short human summary printed by ``python -m limit solve``."""
from __future__ import annotations

from . import mechanism


def _alpha(part: dict) -> str:
    a = part.get("alpha")
    return f"alpha = {a:.6g}" if a is not None else "alpha = -"


def format_result(res: dict) -> str:
    lines = [f"{res['scene']}: {res['dim']}D, {res['n_free_blocks']} free blocks, "
             f"{res['n_interfaces']} interfaces"]
    lp = res["lp"]
    lines.append(f"LP  ({lp['solver']}, {lp['model']['interfaces']} interfaces): {_alpha(lp)}  "
                 f"[{lp['status']}, {lp['time_s']:.3g} s]" + (f"  {lp['reason']}" if lp.get("reason") else ""))
    sol = res.get("_lp_solution")
    if lp["status"] == "optimal" and sol is not None:
        lines.append("  mechanism (associative):")
        lines += ["  " + s for s in mechanism.summary_lines(res["_assembled"], sol.u)]
    nlp = res.get("nlp")
    if nlp:
        lines.append(f"NLP ({nlp.get('solver', '-')}): {_alpha(nlp)}  [{nlp['status']}, {nlp.get('time_s', 0):.3g} s]"
                     + (f"  {nlp['reason']}" if nlp.get("reason") else ""))
        if nlp.get("summary"):
            lines += nlp["summary"]
    return "\n".join(lines)
