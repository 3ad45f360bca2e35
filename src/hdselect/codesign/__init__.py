"""Co-design: the shortest cycle a choice of units allows, ratios compared, the largest payload.

`fastest` runs TOPPRA along the motion's path under the units' limits (`pathbounds`,
`fastpath`), holds the whole-cycle rules (`cyclerules`) and says what binds
(`bindings`); `max_payload` finds the heaviest payload a motion can carry.
"""

from hdselect.codesign.fastest_cycle import FastestResult, RatioComparison, compare_ratios, fastest
from hdselect.codesign.maxpayload import MaxPayloadResult, max_payload

__all__ = ["FastestResult", "MaxPayloadResult", "RatioComparison", "compare_ratios", "fastest",
           "max_payload"]
