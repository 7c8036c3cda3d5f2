// SPDX-License-Identifier: MIT
#pragma once
// The limits every host reader of a run log holds to (host/README.md, "Limits"; issue 38
// §1): at most kMaxRunRows data rows (counted while the file is read, before it is parsed or
// held whole), every du/dy value within ±kMaxRunValue (so sums of squares cannot overflow to
// inf or NaN). They are read options of firmware/runlog, enforced by the reader itself, so a
// log is opened once and no reader can forget them.

#include <cstddef>

#include "firmware/runlog/reader.hpp"

namespace excite::host {

inline constexpr std::size_t kMaxRunRows = 100'000;
inline constexpr double kMaxRunValue = 1e12;

/// `base` with the host's limits; `max_rows` lower for a log read with others (the limit
/// holds for runs pooled together).
inline runlog::ReadOptions limited_read_options(runlog::ReadOptions base = {},
                                                std::size_t max_rows = kMaxRunRows) {
  base.max_rows = max_rows;
  base.max_abs_value = kMaxRunValue;
  base.limits_source = "host/README.md, Limits";
  return base;
}

}  // namespace excite::host
