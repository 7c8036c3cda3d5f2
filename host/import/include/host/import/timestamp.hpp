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

//   - a strftime-style format (`--time-format`, issue 22), for the vendors' forms:
//       %Y year (4 digits)   %y year 00–68 → 2000–2068, 69–99 → 1969–1999
//       %m month (1–2 digits) %b %B %h month name or its 3-letter abbreviation (English)
//       %d %e day (1–2)       %H hour 0–23 (1–2)  %I hour 1–12 with %p AM/PM
//       %M minute (1–2)       %S second (1–2; a fraction `.123` or `,123` may follow)
//       %z zone ±HH:MM, ±HHMM or Z   %F = %Y-%m-%d   %T = %H:%M:%S   %% a percent sign
//     Other characters match themselves; a blank matches one or more blanks.
//
// A timestamp with a zone (Z, an offset, or epoch seconds) is `zoned`; one without is read
// as given (as if UTC) unless a time zone converts it (time_zone.hpp).

#include <optional>
#include <string>
#include <string_view>

namespace excite::host::historian {

struct Timestamp {
  double seconds = 0.0;  // since 1970-01-01T00:00:00Z (naive: as if the local time were UTC)
  bool zoned = false;
};

/// ISO 8601 or epoch seconds, as parse_timestamp(), with whether a zone was given.
std::optional<Timestamp> parse_iso_or_epoch(std::string_view text);

/// `text` read with a strftime-style `format` (the subset above); nullopt when it does not
/// match or a field is out of range.
std::optional<Timestamp> parse_formatted(std::string_view text, std::string_view format);

/// "" when `format` is usable; otherwise what is wrong (an unknown directive, %I without
/// %p, no year, month, day or hour).
std::string check_time_format(std::string_view format);

/// Seconds since the epoch as ISO 8601 UTC, `2026-03-01T08:00:00Z` (whole seconds).
std::string format_utc(double seconds);

/// Seconds since 1970-01-01T00:00:00Z, or nullopt when `text` is neither form (or a field
/// is out of range: month 1–12, day within the month, hour 0–23, minute 0–59, second 0–60).
std::optional<double> parse_timestamp(std::string_view text);

}  // namespace excite::host::historian
