// SPDX-License-Identifier: MIT
#include "host/import/time_zone.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <stdexcept>

namespace excite::host::historian {
namespace {

// The zone's UTC offset (seconds) at instant t.
long offset_at(std::time_t t) {
  std::tm tm{};
  localtime_r(&t, &tm);
  return tm.tm_gmtoff;
}

bool valid_name(const std::string& name) {
  if (name.empty() || name.front() == '/' || name.find("..") != std::string::npos) return false;
  for (const char c : name) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '/' || c == '_' || c == '-' || c == '+';
    if (!ok) return false;
  }
  const char* dir = std::getenv("TZDIR");
  const std::filesystem::path file =
      std::filesystem::path(dir != nullptr && *dir != '\0' ? dir : "/usr/share/zoneinfo") / name;
  std::error_code ec;
  return std::filesystem::is_regular_file(file, ec);
}

}  // namespace

TimeZone::TimeZone(const std::string& name) : name_(name) {
  if (!valid_name(name)) {
    throw std::invalid_argument("--time-zone = " + name +
                                ", expected an IANA zone of the tz database, e.g. Europe/Berlin, "
                                "America/Chicago or UTC (package tzdata)");
  }
  if (const char* old = std::getenv("TZ")) old_tz_ = old;
  setenv("TZ", name.c_str(), 1);
  tzset();
}

TimeZone::~TimeZone() {
  if (old_tz_) {
    setenv("TZ", old_tz_->c_str(), 1);
  } else {
    unsetenv("TZ");
  }
  tzset();
}

TimeZone::Result TimeZone::to_utc(double naive_s) const {
  const double whole = std::floor(naive_s);
  const double fraction = naive_s - whole;
  const auto n = static_cast<std::time_t>(whole);
  // Every instant that reads n on the local clock has one of the offsets in force around it.
  const long offsets[] = {offset_at(n - 2 * 86400), offset_at(n), offset_at(n + 2 * 86400)};
  std::time_t found[3];
  int count = 0;
  for (const long o : offsets) {
    const std::time_t c = n - o;
    if (offset_at(c) != o) continue;
    bool seen = false;
    for (int i = 0; i < count; ++i) seen = seen || found[i] == c;
    if (!seen) found[count++] = c;
  }
  Result r;
  if (count == 0) {
    r.status = Local::skipped;
    return r;
  }
  std::time_t first = found[0], last = found[0];
  for (int i = 1; i < count; ++i) {
    first = std::min(first, found[i]);
    last = std::max(last, found[i]);
  }
  r.status = count > 1 ? Local::ambiguous : Local::ok;
  r.utc_s = static_cast<double>(first) + fraction;
  r.later_s = static_cast<double>(last) + fraction;
  return r;
}

}  // namespace excite::host::historian
