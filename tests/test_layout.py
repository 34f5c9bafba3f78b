"""The package layout: no import circle among the project's own modules, and the learning core
(``agents/core``) stands on its own, below the training driver, the study and the analyses.

Imports are read from the source with ``ast`` (every ``import`` statement, also those inside
functions), so an import that runs only on some calls counts too."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("agents", "dynnav_tasks")
ABOVE_CORE = ("agents.training", "agents.study", "agents.analysis", "agents.imitation")
"""what agents.core must not import: the layers that use it"""


def module_names(root: Path = ROOT) -> dict[str, Path]:
    """Every module of the project's packages: dotted name -> file (a package is its __init__)."""
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def imported_modules(name: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The project modules that module ``name`` (at ``path``) imports, anywhere in its code.

    ``from a.b import c`` imports the module a.b.c if there is one, else takes c from a.b."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names]
        else:
            continue
        for target in targets:
            while target and target not in modules:  # ``import a.b.c`` of a non-module c: a.b
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


def import_graph(root: Path = ROOT) -> dict[str, set[str]]:
    """Module -> the project modules it imports."""
    modules = module_names(root)
    return {name: imported_modules(name, path, modules) for name, path in modules.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle of ``graph`` as [a, b, ..., a], or None (depth-first search)."""
    state, stack = {}, []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        stack.pop()
        state[node] = "done"
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def test_the_graph_sees_every_kind_of_import(tmp_path):
    """Absolute, from-, relative and function-level imports all make edges, and a circle is found."""
    pkg = tmp_path / "agents"
    (pkg / "core").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "core" / "__init__.py").write_text("")
    (pkg / "core" / "a.py").write_text("from agents.core import b\n")
    (pkg / "core" / "b.py").write_text("def f():\n    from .c import g\n")
    (pkg / "core" / "c.py").write_text("import agents.core.a\n")
    (tmp_path / "dynnav_tasks").mkdir()
    (tmp_path / "dynnav_tasks" / "__init__.py").write_text("from .x import y\n")
    (tmp_path / "dynnav_tasks" / "x.py").write_text("y = 1\n")
    graph = import_graph(tmp_path)
    assert graph["agents.core.a"] == {"agents.core.b"}
    assert graph["agents.core.b"] == {"agents.core.c"}
    assert graph["dynnav_tasks"] == {"dynnav_tasks.x"}
    assert find_cycle(graph) == ["agents.core.a", "agents.core.b", "agents.core.c", "agents.core.a"]
    (pkg / "core" / "c.py").write_text("import numpy\n")
    assert find_cycle(import_graph(tmp_path)) is None


def test_no_import_circle():
    graph = import_graph()
    assert len(graph) > 50 and "agents.training.loop" in graph["agents.dqn"]
    cycle = find_cycle(graph)
    assert cycle is None, "import circle: " + " -> ".join(cycle)


@pytest.mark.parametrize("module", sorted(m for m in import_graph() if m.startswith("agents.core")))
def test_the_learning_core_imports_nothing_above_it(module):
    above = sorted(m for m in import_graph()[module] if m.startswith(ABOVE_CORE))
    assert not above, f"{module} imports {', '.join(above)}: agents.core must not depend on the training driver"


def test_nothing_imports_the_imitation_room():
    """Its students are DQN checkpoints and its data a file: the rest reads them without importing it."""
    graph = import_graph()
    outside = {m: sorted(t for t in targets if t.startswith("agents.imitation"))
               for m, targets in graph.items() if not m.startswith("agents.imitation")}
    assert not {m: t for m, t in outside.items() if t}
