// SPDX-License-Identifier: MIT
#pragma once
// Deviation limits of a plan against its generated table.

#include <cstdint>

#include "firmware/plan/plan.hpp"
#include "firmware/signal/table.hpp"

namespace excite::plan {

struct [[nodiscard]] LimitCheck {
  Status status;              // ok when every value lies in [min, max] of its channel
  std::uint32_t channel = 0;  // first violation in table order (sample, then channel)
  std::uint32_t sample = 0;
  double value = 0.0;
};

/// Scans `table` (the plan's generated table: same channels and samples, else
/// invalid_field) for the first value outside meta.channels[c].[min, max] (NaN counts as
/// outside) and reports it with StatusCode::limit_violated and a message like
/// "table(sample 117, channel 2 \"reflux L\") = 3.5, expected within [-2, 2]".
LimitCheck check_limits(const Plan& plan, signal::ConstTableView table);

}  // namespace excite::plan
