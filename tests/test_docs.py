"""Every example of README.md and docs/*.md prints what its page shows (see docs_examples)."""

from __future__ import annotations

import difflib
import re
from pathlib import Path

import pytest

from docs_examples import OWN_ROBOT, PAGES, ROOT, Example, examples, matches, run, scratch

OWN_TESTS = {
    "bad-input.md": "test_bad_input_docs.py",
    "review.md": "test_review_docs.py",
    "tool-poses.md": "test_toolposes.py",
}
"""Pages whose examples a test of their own runs (files it prepares, statuses it checks)."""

GUIDE = [page for page in PAGES if page.name not in OWN_TESTS]
"""The pages run here."""


def page_examples(page: Path) -> list[Example]:
    """A page's examples; the README's without its "Your own robot" steps."""
    text = page.read_text(encoding="utf-8")
    if page.name == "README.md" and OWN_ROBOT in text:
        start = text.index(OWN_ROBOT)
        end = text.find("\n## ", start + 1)
        text = text[:start] + (text[end:] if end >= 0 else "")
    return examples(page, text)


@pytest.mark.slow
@pytest.mark.parametrize("page", GUIDE, ids=lambda page: page.name)
def test_every_example_prints_what_the_page_shows(page, tmp_path):
    work = scratch(tmp_path)
    failures = []
    for example in page_examples(page):
        printed = run(example, work)
        if example.shown is not None and printed is not None \
                and not matches(printed, example.shown):
            diff = "\n".join(difflib.unified_diff(example.shown.split("\n"),
                                                  printed.split("\n"), "page", "printed",
                                                  lineterm=""))
            failures.append(f"{example.source.splitlines()[0]}\n{diff}")
    assert failures == [], "\n\n".join(failures)


def test_the_pages_examples_leave_nothing_in_the_repository(tmp_path):
    """Outputs go to out/ in the scratch folder; the shipped folders stay as they are."""
    for page in GUIDE:
        for example in page_examples(page):
            if example.kind == "file":
                assert example.shown.startswith("out/"), example
            elif example.kind == "console":
                for word in example.source.split()[1:]:
                    assert not (word.endswith((".csv", ".png", ".json", ".jsonl"))
                                and not word.startswith("out/") and word != "-"), example


def test_ellipsis_stands_for_any_lines_and_only_there():
    assert matches("a\nb\nc\nd", "a\n...\nd")
    assert matches("a\nd", "a\n...\nd")
    assert matches("a\nb\nc", "a\n...")
    assert matches("a\nb\nc", "...\nb\n...")
    assert not matches("a\nb\nc", "a\n...\nb\nd")
    assert not matches("a\nb", "a\nb\nc")
    assert not matches("a\nx\nc", "a\nb\nc")
    assert not matches("a", "a\n...\na")


def test_a_page_left_to_its_own_test_is_run_there():
    for page in PAGES:
        if page.name in OWN_TESTS:
            test = ROOT / "tests" / OWN_TESTS[page.name]
            assert page.name in test.read_text(encoding="utf-8"), test


def test_every_guide_page_runs_examples_and_every_console_line_runs_hdselect():
    for page in GUIDE:
        found = page_examples(page)
        for example in found:
            if example.kind == "console":
                assert example.source.startswith("hdselect "), example
        if page.name not in ("architecture.md", "performance.md", "changes.md"):
            assert any(e.kind != "file" and e.shown for e in found), page.name
    assert {p.name for p in PAGES} >= {"README.md", "sizing.md", "rules.md", "python-api.md"}


def test_the_python_page_runs_every_public_name():
    import hdselect

    page = ROOT / "docs" / "python-api.md"
    code = "\n".join(e.source for e in examples(page) if e.kind == "python")
    missing = [name for name in hdselect.__all__
               if not re.search(rf"\bhdselect\.(study\.)?{re.escape(name)}\b", code)]
    assert missing == []


def anchor(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def test_every_link_between_the_pages_resolves():
    broken = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"\w+://", target):
                continue
            path, _, fragment = target.partition("#")
            file = (page.parent / path).resolve() if path else page
            if not file.exists():
                if not _still_coming(file):
                    broken.append(f"{page.name}: {target}")
            elif fragment and file.suffix == ".md":
                headings = re.findall(r"^#+ (.*)$", file.read_text(encoding="utf-8"), re.M)
                if fragment not in {anchor(h) for h in headings}:
                    broken.append(f"{page.name}: {target}")
    assert broken == []


def _still_coming(file) -> bool:
    """A page of `OWN_TESTS` whose branch has not landed yet: neither it nor its test is here.

    Once its test is in the repository, the page must be too.
    """
    return (file.parent == ROOT / "docs" and file.name in OWN_TESTS
            and not (ROOT / "tests" / OWN_TESTS[file.name]).exists())
