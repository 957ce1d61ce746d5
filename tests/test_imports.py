"""The library's modules import one another without a circle (issue: analysis <-> nlp,
nlp <-> step2_large), counting imports inside functions too: a circle would mean two
modules that cannot be read one after the other. And data flows one way through the
subpackages: geom -> model -> solve -> results -> verdict -> the top-level drivers
(the leaves limit.errors and limit.settings excepted: they import nothing from limit)."""
import ast
from pathlib import Path

LIMIT = Path(__file__).resolve().parent.parent / "limit"
#: the subpackages in the order data flows through them; "top" is limit/*.py
LAYERS = ["geom", "model", "solve", "results", "verdict", "top"]
#: top-level modules every layer may import: they import nothing from limit
LEAVES = ("limit.errors", "limit.settings")


def _name(p: Path) -> str:
    rel = p.relative_to(LIMIT.parent).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def _edges() -> dict:
    """module -> the limit modules it imports (dotted names), from every import statement."""
    files = {_name(p): p for p in LIMIT.rglob("*.py")}
    edges = {m: set() for m in files}
    for m, p in files.items():
        pkg = m if p.name == "__init__.py" else m.rpartition(".")[0]
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                    base = ".".join(up + ([base] if base else []))
                targets = [f"{base}.{a.name}" for a in node.names] + [base]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            edges[m].update(t for t in targets if t in files and t != m and t != "limit")
    return edges


def _layer(m: str) -> str:
    parts = m.split(".")
    return parts[1] if len(parts) >= 2 and parts[1] in LAYERS else "top"


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
    # the check sees real edges
    assert {"limit.solve.nlp", "limit.solve.step2_large"} <= edges["limit.step2"]
    assert "limit.model.scene" in edges["limit.api"]


def test_data_flows_one_way_through_the_subpackages():
    edges = _edges()
    back = [(m, d) for m, ds in edges.items() for d in ds
            if d not in LEAVES and LAYERS.index(_layer(d)) > LAYERS.index(_layer(m))]
    assert not back, f"imports against the data flow {' -> '.join(LAYERS)}: {back}"
    assert all(not edges[leaf] for leaf in LEAVES), {leaf: edges[leaf] for leaf in LEAVES}
    assert "limit.settings" in edges["limit.model.assemble"]
    assert _layer("limit.geom._clip") == "geom" and _layer("limit.analysis") == "top"
