"""The registered rules that give a solver form."""

from __future__ import annotations

from hdselect.catalog.rules import RULES, Rule


def giving(form: str) -> list[str]:
    """The registered rules that define the solver form `form` (a method of `Rule`)."""
    return [found.name for found in RULES if getattr(type(found), form) is not getattr(Rule, form)]
