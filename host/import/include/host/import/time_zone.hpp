// SPDX-License-Identifier: MIT
#pragma once
// Local times of an IANA time zone → UTC (issue 22, `--time-zone Europe/Berlin`), with the
// C library's tz database (the tzdata package: /usr/share/zoneinfo, or $TZDIR).
//
// A local time maps to one instant, except around a daylight-saving change: in the hour
// skipped in spring it names no instant (`skipped`), in the hour repeated in autumn it
// names two (`ambiguous`); import refuses both by line, as an export in local time cannot
// say which instant it meant.
//
// The zone is selected through the process's TZ variable while the object lives (the old
// value is restored by the destructor): one TimeZone at a time, from one thread.

#include <optional>
#include <string>

namespace excite::host::historian {

class TimeZone {
 public:
  /// Throws std::invalid_argument when `name` is not a zone of the database.
  explicit TimeZone(const std::string& name);
  ~TimeZone();
  TimeZone(const TimeZone&) = delete;
  TimeZone& operator=(const TimeZone&) = delete;

  enum class Local { ok, skipped, ambiguous };
  struct Result {
    Local status = Local::ok;
    double utc_s = 0.0;    // ok: the instant; ambiguous: the earlier of the two
    double later_s = 0.0;  // ambiguous: the later of the two
  };
  /// `naive_s`: the local wall-clock time as if it were UTC (timestamp.hpp's `seconds`).
  Result to_utc(double naive_s) const;
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::optional<std::string> old_tz_;
};

}  // namespace excite::host::historian
