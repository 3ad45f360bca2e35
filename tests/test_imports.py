"""The package tree is the data flow that docs/architecture.md draws.

The listing under "Packages, in the order data flows" names every package in the
order data flows through them, and every module of each package in the order its
imports allow. Every import of an hdselect module (function-local imports
included) must point to an earlier package, or to an earlier module of its own
package; so the imports form no cycle.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from helpers import REPO

PACKAGE = REPO / "src" / "hdselect"
DOC = REPO / "docs" / "architecture.md"


def listing() -> list[tuple[str, list[str]]]:
    """Each package of the architecture page, with its modules in order."""
    section = DOC.read_text().split("## Packages, in the order data flows", 1)[1]
    block = section.split("```", 2)[1]
    rows = []
    for line in block.splitlines():
        match = re.fullmatch(r"(\w+)/\s+(.*)", line.strip())
        if match:
            rows.append((match[1], match[2].split()))
    return rows


def module_of(path: Path) -> tuple[str, str] | None:
    """(package, module) of a source file; a sub-package counts as one module ("planning/")."""
    parts = path.relative_to(PACKAGE).parts
    if len(parts) == 1:
        return None
    stem = parts[1].removesuffix(".py")
    if len(parts) > 2:
        return parts[0], f"{stem}/"
    return (parts[0], stem) if stem not in ("__init__", "__main__") else (parts[0], "")


def imports() -> dict[tuple[str, str], set[tuple[str, str]]]:
    """(package, module) -> the (package, module) it imports; "" is a package's __init__."""
    graph: dict[tuple[str, str], set[tuple[str, str]]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        source = module_of(path)
        if source is None:
            continue
        targets = graph.setdefault(source, set())
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = []
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module]
            elif isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            for name in names:
                parts = name.split(".")
                if parts[0] != "hdselect" or len(parts) < 2:
                    continue
                module = ""
                if len(parts) > 2:
                    module = parts[2] + ("/" if (PACKAGE / parts[1] / parts[2]).is_dir() else "")
                targets.add((parts[1], module))
        targets.discard(source)
    return graph


def test_every_package_and_module_is_listed_once():
    rows = listing()
    packages = [name for name, _ in rows]
    on_disk = sorted(p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists())
    assert sorted(packages) == on_disk and len(set(packages)) == len(packages)
    listed = {(package, module) for package, modules in rows for module in modules}
    assert sum(len(modules) for _, modules in rows) == len(listed), "a module is listed twice"
    found = {key for key in imports() if key[1]}
    assert listed == found, "the page and the source tree list other modules"


def test_imports_point_up_the_flow():
    rows = listing()
    package_rank = {name: i for i, (name, _) in enumerate(rows)}
    module_rank = {(name, module): i for name, modules in rows for i, module in enumerate(modules)}
    backwards = []
    for source, targets in imports().items():
        for target in targets:
            if package_rank[target[0]] > package_rank[source[0]]:
                backwards.append((source, target))
            elif (target[0] == source[0] and target[1] and source[1]
                  and module_rank[target] >= module_rank[source]):
                backwards.append((source, target))
            elif target[0] == source[0] and not target[1] and source[1]:
                backwards.append((source, target))  # a module importing its own package
    assert backwards == []


def test_modules_stay_short():
    long = {str(path.relative_to(PACKAGE)): n for path in PACKAGE.rglob("*.py")
            if (n := len(path.read_text().splitlines())) > 450}
    assert long == {}, "a module over 450 lines holds more than one step"
