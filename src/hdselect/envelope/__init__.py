"""Size a robot before its task is known: the worst case over every motion within a spec.

`envelope` searches each joint's worst states over the limit box (joint ranges,
|qd| <= v, |qdd| <= a) and hands them, beside a duty's samples, to the one selection
of `hdselect.sizing.core`. The package is callable: ``hdselect.envelope(robot, ...)``
is `envelope`, and ``hdselect.envelope.SearchSettings`` still works.
"""

from __future__ import annotations

import inspect
import sys
import types

from hdselect.envelope.records import envelope_json
from hdselect.envelope.result import EnvelopeResult, JointEnvelope, WorstState
from hdselect.envelope.run import envelope
from hdselect.envelope.search import SearchSettings

__all__ = ["EnvelopeResult", "JointEnvelope", "SearchSettings", "WorstState", "envelope",
           "envelope_json"]


class _CallableModule(types.ModuleType):
    """This package, callable as the function `envelope` it exports, with its signature."""

    __call__ = staticmethod(envelope)
    __signature__ = inspect.signature(envelope)


sys.modules[__name__].__class__ = _CallableModule
