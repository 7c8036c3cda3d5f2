// SPDX-License-Identifier: MIT
#pragma once
// The gateway's accepted timing, in one place (README "Timing is range-checked"): the tick
// period (gateway.period_s, or the plan's sample time) within [kMinPeriodS, kMaxPeriodS];
// every other duration within [0, kMaxDurationS]. excite-plant checks its wall-clock
// seconds per sample and its sample time against the same period range (issue 19 item 4).

namespace excite::app {

inline constexpr double kMinPeriodS = 1e-3;
inline constexpr double kMaxPeriodS = 86400.0;
inline constexpr double kMaxDurationS = 1e6;

}  // namespace excite::app
