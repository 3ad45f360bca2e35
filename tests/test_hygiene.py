"""What the source and its pages name exists, and library code checks instead of asserting.

- Every dotted ``hdselect.package.module.name`` written in src/ (code, docstrings,
  comments) or docs/ imports and resolves, so a moved or renamed module leaves no
  dangling reference behind.
- Every ``*.md`` page named in src/ or tests/ is a page of the project (README.md or
  one in docs/).
- Library code holds no ``assert`` statement (``python -O`` strips them, and a failed
  one is no error a caller can catch): it raises an `HdselectError` for bad input, or a
  RuntimeError/TypeError naming the broken invariant.
- No module but a package's ``__init__`` re-exports (``noqa: F401``): a name is imported
  from its home.
"""

from __future__ import annotations

import ast
import importlib
import re
import warnings
from pathlib import Path

from helpers import REPO

SOURCE = REPO / "src" / "hdselect"
DOTTED = re.compile(r"\bhdselect(?:\.[A-Za-z_]\w*)+")
PAGE = re.compile(r"\b[A-Za-z][\w-]*\.md\b")


def _resolves(name: str) -> bool:
    """Whether the dotted name imports as a module, or as attributes of one."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            found: object = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        with warnings.catch_warnings():  # a deprecated spelling still resolves
            warnings.simplefilter("ignore", DeprecationWarning)
            for attribute in parts[k:]:
                if not hasattr(found, attribute):
                    return False
                found = getattr(found, attribute)
        return True
    return False


HISTORY = REPO / "docs" / "changes.md"
"""What changed between versions: it names modules as they were, on purpose."""


def _texts() -> list[Path]:
    return sorted([*SOURCE.rglob("*.py"),
                   *(page for page in (REPO / "docs").rglob("*.md") if page != HISTORY)])


def _library() -> list[Path]:
    return sorted(SOURCE.rglob("*.py"))


def test_every_dotted_hdselect_name_resolves():
    dangling = []
    for path in _texts():
        for number, line in enumerate(path.read_text().splitlines(), 1):
            for match in DOTTED.finditer(line):
                if not _resolves(match[0]):
                    dangling.append(f"{path.relative_to(REPO)}:{number}: {match[0]}")
    assert dangling == []


def test_the_resolver_finds_a_dangling_name():
    assert _resolves("hdselect.base.bounds.TIME_SCALE")
    assert not _resolves("hdselect.bounds")
    assert not _resolves("hdselect.base.bounds.NO_SUCH_BOUND")


def test_every_page_named_exists():
    pages = {"README.md", *(path.name for path in (REPO / "docs").rglob("*.md"))}
    missing = []
    for path in sorted([*SOURCE.rglob("*.py"), *(REPO / "tests").glob("*.py")]):
        for number, line in enumerate(path.read_text().splitlines(), 1):
            missing += [f"{path.relative_to(REPO)}:{number}: {name}"
                        for name in PAGE.findall(line) if name not in pages]
    assert missing == []


def test_library_code_raises_instead_of_asserting():
    asserts = [f"{path.relative_to(REPO)}:{node.lineno}" for path in _library()
               for node in ast.walk(ast.parse(path.read_text(), str(path)))
               if isinstance(node, ast.Assert)]
    assert asserts == []


def test_no_module_re_exports_another():
    """A package's ``__init__`` gathers its modules' names; any other module is no shim."""
    shims = [str(path.relative_to(REPO)) for path in _library()
             if path.name != "__init__.py" and "noqa: F401" in path.read_text()]
    assert shims == []
