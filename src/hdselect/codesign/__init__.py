"""Co-design: the shortest cycle a choice of units allows, ratios compared, the largest payload.

`fastest` runs TOPPRA along the motion's path under the units' limits (`pathbounds`,
`fastpath`), holds the whole-cycle rules (`cyclerules`) and says what binds
(`bindings`); `max_payload` finds the heaviest payload a motion can carry; `mix_fastest`
and `mix_max_payload` do both for a mix of motions (`mixfastest`, `mixpayload`).
"""

from hdselect.codesign.fastest_cycle import FastestResult, RatioComparison, compare_ratios, fastest
from hdselect.codesign.maxpayload import MaxPayloadResult, max_payload
from hdselect.codesign.mixfastest import MixFastestResult, mix_fastest
from hdselect.codesign.mixpayload import MixPayloadResult, mix_max_payload

__all__ = ["FastestResult", "MaxPayloadResult", "MixFastestResult", "MixPayloadResult",
           "RatioComparison", "compare_ratios", "fastest", "max_payload", "mix_fastest",
           "mix_max_payload"]
