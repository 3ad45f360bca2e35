"""Co-design: the shortest cycle a choice of units allows, ratios compared, the largest payload.

`fastest` runs every task's path (a motion is a duty of one task; a mix has several)
under the units' limits (`pathbounds`, `fastpath`), holds the whole-cycle rules over
the duty (`cyclerules`, `trials`) and says what binds (`bindings`); `compare_ratios`
does it for every unit on each joint; `max_payload` finds the heaviest payload a motion
(or the largest factor on a mix's payloads) leaves a unit on every joint.
"""

from typing import Any

from hdselect.base.errors import deprecated
from hdselect.codesign.fastest_cycle import FastestResult, RatioComparison, compare_ratios, fastest
from hdselect.codesign.maxpayload import MaxPayloadResult, max_payload

__all__ = ["FastestResult", "MaxPayloadResult", "RatioComparison", "compare_ratios", "fastest",
           "max_payload"]

_RENAMED = {"mix_fastest": ("fastest", fastest),
            "MixFastestResult": ("FastestResult", FastestResult),
            "mix_max_payload": ("max_payload", max_payload),
            "MixPayloadResult": ("MaxPayloadResult", MaxPayloadResult)}


def __getattr__(name: str) -> Any:
    """The old spellings of the mix's co-design, with a DeprecationWarning naming the new."""
    if name in _RENAMED:
        new, value = _RENAMED[name]
        deprecated(f"hdselect.codesign.{name}", f"hdselect.codesign.{new} (it takes a mix "
                   "wherever it takes a motion)")
        return value
    raise AttributeError(f"module 'hdselect.codesign' has no attribute {name!r}")
