"""The library's modules import one another without a circle (issue: analysis <-> nlp,
nlp <-> step2_large), counting imports inside functions too: a circle would mean two
modules that cannot be read one after the other."""
import ast
from pathlib import Path

LIMIT = Path(__file__).resolve().parent.parent / "limit"


def _edges() -> dict:
    mods = {p.stem for p in LIMIT.glob("*.py")}
    edges = {m: set() for m in mods}
    for m in mods:
        for node in ast.walk(ast.parse((LIMIT / f"{m}.py").read_text())):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                names = [node.module.split(".")[0]] if node.module else [a.name for a in node.names]
                edges[m].update(n for n in names if n in mods)
    return edges


def test_no_import_circle_in_limit():
    edges = _edges()
    state, circles = {}, []

    def visit(m, path):
        state[m] = "open"
        for d in sorted(edges[m]):
            if state.get(d) == "open":
                circles.append(path[path.index(d):] + [d])
            elif d not in state:
                visit(d, path + [d])
        state[m] = "done"

    for m in sorted(edges):
        if m not in state:
            visit(m, [m])
    assert not circles, f"import circles: {circles}"
    assert "nlp" in edges["step2"] and "step2_large" in edges["step2"]  # the check sees real edges
