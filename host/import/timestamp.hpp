// SPDX-License-Identifier: MIT
#pragma once
// Historian timestamps → seconds since the Unix epoch (issue 13 §1).
//
// Accepted forms:
//   - ISO 8601 date and time, `T` or one space between them:
//       YYYY-MM-DDTHH:MM[:SS[.fraction]][Z | ±HH:MM | ±HHMM | ±HH]
//     A time with a zone is converted to UTC; a time without one is read as given (all
//     rows are taken to be in the same zone: a local-time export that crosses a daylight
//     saving change shows up as a jump or as timestamps that go back, which import refuses).
//   - epoch seconds: a decimal number (integer or with a fraction), e.g. 1700000000.5.

#include <optional>
#include <string_view>

namespace excite::host::historian {

/// Seconds since 1970-01-01T00:00:00Z, or nullopt when `text` is neither form (or a field
/// is out of range: month 1–12, day within the month, hour 0–23, minute 0–59, second 0–60).
std::optional<double> parse_timestamp(std::string_view text);

}  // namespace excite::host::historian
