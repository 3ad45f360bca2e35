"""The README's data-flow diagram is the import graph: no cycle, no module reaching back.

The diagram under "Where every number comes from" lists the modules in the
order data flows through them, one step per line. Every import of one hdselect
module by another (function-local imports included) must point to the same
line or an earlier one, and the imports must form no cycle.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from test_dynamics import REPO

PACKAGE = REPO / "src" / "hdselect"


def module_name(path: Path) -> str:
    """``planning`` for planning/__init__.py and planning/ruckig.py alike; else the stem."""
    relative = path.relative_to(PACKAGE)
    return relative.parts[0] if len(relative.parts) > 1 else relative.stem


def imports() -> dict[str, set[str]]:
    """Module -> the hdselect modules it imports (modules of a sub-package count as one)."""
    graph: dict[str, set[str]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        source = module_name(path)
        targets = graph.setdefault(source, set())
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module]
            elif isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            for name in names:
                parts = name.split(".")
                if parts[0] == "hdselect" and len(parts) > 1:
                    targets.add(parts[1])
        targets.discard(source)
    graph.pop("__init__")  # the package's public face imports from everywhere
    return graph


def diagram_lines() -> list[set[str]]:
    """The modules named on each line of the README's data-flow diagram, in order."""
    text = (REPO / "README.md").read_text()
    section = text.split("## Where every number comes from", 1)[1]
    block = section.split("```", 2)[1]
    lines = []
    for line in block.splitlines():
        names = set(re.findall(r"\b([a-z_]+)(?:\.py|/)", line))
        if names:
            lines.append(names)
    return lines


def test_every_module_is_in_the_diagram_once():
    lines = diagram_lines()
    named = [name for line in lines for name in line]
    assert sorted(named) == sorted(set(named)), "a module is named twice"
    assert set(named) == set(imports()), "the diagram and the package list other modules"


def test_no_module_imports_one_further_down_the_flow():
    rank = {name: i for i, line in enumerate(diagram_lines()) for name in line}
    backwards = [(source, target) for source, targets in imports().items()
                 for target in targets if rank[target] > rank[source]]
    assert backwards == []


def test_the_imports_form_no_cycle():
    graph = imports()
    state: dict[str, str] = {}

    def visit(node: str, path: list[str]) -> None:
        state[node] = "open"
        for target in sorted(graph[node]):
            assert state.get(target) != "open", " -> ".join([*path, node, target])
            if target not in state:
                visit(target, [*path, node])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [])
