// SPDX-License-Identifier: MIT
#include "host/import/timestamp.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>

namespace excite::host::historian {
namespace {

// Days from 1970-01-01 to y-m-d in the proleptic Gregorian calendar (H. Hinnant's
// days_from_civil).
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

bool leap(std::int64_t y) {
  return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

unsigned days_in_month(std::int64_t y, unsigned m) {
  static constexpr unsigned kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leap(y) ? 29 : kDays[m - 1];
}

// Reads exactly `n` digits at s[pos]; advances pos.
bool digits(std::string_view s, std::size_t& pos, std::size_t n, unsigned& out) {
  if (pos + n > s.size()) return false;
  out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const char c = s[pos + i];
    if (c < '0' || c > '9') return false;
    out = out * 10 + static_cast<unsigned>(c - '0');
  }
  pos += n;
  return true;
}

bool expect(std::string_view s, std::size_t& pos, char c) {
  if (pos >= s.size() || s[pos] != c) return false;
  ++pos;
  return true;
}

std::optional<Timestamp> parse_iso(std::string_view s) {
  std::size_t pos = 0;
  unsigned year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  if (!digits(s, pos, 4, year) || !expect(s, pos, '-') || !digits(s, pos, 2, month) ||
      !expect(s, pos, '-') || !digits(s, pos, 2, day)) {
    return std::nullopt;
  }
  if (pos >= s.size() || (s[pos] != 'T' && s[pos] != ' ')) return std::nullopt;
  ++pos;
  if (!digits(s, pos, 2, hour) || !expect(s, pos, ':') || !digits(s, pos, 2, minute)) {
    return std::nullopt;
  }
  double fraction = 0.0;
  if (pos < s.size() && s[pos] == ':') {
    ++pos;
    if (!digits(s, pos, 2, second)) return std::nullopt;
    if (pos < s.size() && (s[pos] == '.' || s[pos] == ',')) {
      ++pos;
      double scale = 0.1;
      const std::size_t start = pos;
      while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos])) != 0) {
        fraction += scale * (s[pos] - '0');
        scale /= 10.0;
        ++pos;
      }
      if (pos == start) return std::nullopt;
    }
  }
  int offset_min = 0;
  const bool zoned = pos < s.size();
  if (pos < s.size()) {
    if (s[pos] == 'Z' || s[pos] == 'z') {
      ++pos;
    } else if (s[pos] == '+' || s[pos] == '-') {
      const int sign = s[pos] == '-' ? -1 : 1;
      ++pos;
      unsigned oh = 0, om = 0;
      if (!digits(s, pos, 2, oh)) return std::nullopt;
      if (pos < s.size() && s[pos] == ':') ++pos;
      if (pos < s.size() && !digits(s, pos, 2, om)) return std::nullopt;
      if (oh > 23 || om > 59) return std::nullopt;
      offset_min = sign * static_cast<int>(oh * 60 + om);
    } else {
      return std::nullopt;
    }
  }
  if (pos != s.size()) return std::nullopt;
  if (month < 1 || month > 12 || day < 1 || day > days_in_month(year, month) || hour > 23 ||
      minute > 59 || second > 60) {
    return std::nullopt;
  }
  const std::int64_t days = days_from_civil(year, month, day);
  const double seconds = static_cast<double>(days) * 86400.0 + hour * 3600.0 + minute * 60.0 +
                         second + fraction - offset_min * 60.0;
  return Timestamp{seconds, zoned};
}

// Howard Hinnant's civil_from_days.
void civil_from_days(std::int64_t z, std::int64_t& y, unsigned& m, unsigned& d) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  d = doy - (153 * mp + 2) / 5 + 1;
  m = mp < 10 ? mp + 3 : mp - 9;
  y = static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0);
}

// 1 to `max_digits` digits at s[pos].
bool some_digits(std::string_view s, std::size_t& pos, std::size_t max_digits, unsigned& out) {
  const std::size_t start = pos;
  out = 0;
  while (pos < s.size() && pos - start < max_digits && s[pos] >= '0' && s[pos] <= '9') {
    out = out * 10 + static_cast<unsigned>(s[pos] - '0');
    ++pos;
  }
  return pos > start;
}

bool blank(char c) {
  return c == ' ' || c == '\t';
}

constexpr const char* kMonths[] = {"january",   "february", "march",    "april",
                                   "may",       "june",     "july",     "august",
                                   "september", "october",  "november", "december"};

bool month_name(std::string_view s, std::size_t& pos, unsigned& month) {
  const auto lower_at = [&](std::size_t i) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(s[i])));
  };
  for (unsigned m = 0; m < 12; ++m) {
    const std::string_view name = kMonths[m];
    std::size_t n = 0;
    while (n < name.size() && pos + n < s.size() && lower_at(pos + n) == name[n]) ++n;
    if (n == name.size() || n == 3) {  // the full name or its abbreviation
      month = m + 1;
      pos += n;
      return true;
    }
  }
  return false;
}

bool zone_offset(std::string_view s, std::size_t& pos, int& offset_min) {
  if (pos < s.size() && (s[pos] == 'Z' || s[pos] == 'z')) {
    ++pos;
    offset_min = 0;
    return true;
  }
  if (pos >= s.size() || (s[pos] != '+' && s[pos] != '-')) return false;
  const int sign = s[pos] == '-' ? -1 : 1;
  ++pos;
  unsigned oh = 0, om = 0;
  if (!digits(s, pos, 2, oh)) return false;
  if (pos < s.size() && s[pos] == ':') ++pos;
  if (!digits(s, pos, 2, om) || oh > 23 || om > 59) return false;
  offset_min = sign * static_cast<int>(oh * 60 + om);
  return true;
}

struct Fields {
  std::int64_t year = -1;
  unsigned month = 0, day = 0, hour = 0, minute = 0, second = 0;
  double fraction = 0.0;
  int pm = -1;  // -1: no %p
  bool zoned = false;
  int offset_min = 0;
};

bool match(std::string_view s, std::size_t& pos, std::string_view f, Fields& x);

bool directive(std::string_view s, std::size_t& pos, char d, char next_literal, Fields& x) {
  unsigned v = 0;
  switch (d) {
    case 'Y':
      if (!some_digits(s, pos, 4, v)) return false;
      x.year = v;
      return true;
    case 'y':
      if (!some_digits(s, pos, 2, v)) return false;
      x.year = v < 69 ? 2000 + v : 1900 + v;
      return true;
    case 'm':
      return some_digits(s, pos, 2, x.month);
    case 'b':
    case 'B':
    case 'h':
      return month_name(s, pos, x.month);
    case 'd':
    case 'e':
      while (d == 'e' && pos < s.size() && blank(s[pos])) ++pos;
      return some_digits(s, pos, 2, x.day);
    case 'H':
    case 'I':
      return some_digits(s, pos, 2, x.hour);
    case 'M':
      return some_digits(s, pos, 2, x.minute);
    case 'S':
      if (!some_digits(s, pos, 2, x.second)) return false;
      if (pos + 1 < s.size() && (s[pos] == '.' || s[pos] == ',') && s[pos] != next_literal &&
          s[pos + 1] >= '0' && s[pos + 1] <= '9') {
        ++pos;
        double scale = 0.1;
        while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') {
          x.fraction += scale * (s[pos] - '0');
          scale /= 10.0;
          ++pos;
        }
      }
      return true;
    case 'p': {
      if (pos + 1 >= s.size()) return false;
      const char a = static_cast<char>(std::toupper(static_cast<unsigned char>(s[pos])));
      const char b = static_cast<char>(std::toupper(static_cast<unsigned char>(s[pos + 1])));
      if ((a != 'A' && a != 'P') || b != 'M') return false;
      x.pm = a == 'P' ? 1 : 0;
      pos += 2;
      return true;
    }
    case 'z':
      x.zoned = true;
      return zone_offset(s, pos, x.offset_min);
    case 'F':
      return match(s, pos, "%Y-%m-%d", x);
    case 'T':
      return match(s, pos, "%H:%M:%S", x);
    case '%':
      return expect(s, pos, '%');
    default:
      return false;
  }
}

bool match(std::string_view s, std::size_t& pos, std::string_view f, Fields& x) {
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f[i] == '%' && i + 1 < f.size()) {
      const char next = i + 2 < f.size() && f[i + 2] != '%' ? f[i + 2] : '\0';
      if (!directive(s, pos, f[i + 1], next, x)) return false;
      ++i;
    } else if (blank(f[i])) {
      if (pos >= s.size() || !blank(s[pos])) return false;
      while (pos < s.size() && blank(s[pos])) ++pos;
    } else if (!expect(s, pos, f[i])) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::optional<Timestamp> parse_iso_or_epoch(std::string_view text) {
  if (text.empty()) return std::nullopt;
  if (text.size() >= 10 && text[4] == '-') return parse_iso(text);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return Timestamp{v, true};
}

std::optional<double> parse_timestamp(std::string_view text) {
  const std::optional<Timestamp> t = parse_iso_or_epoch(text);
  if (!t) return std::nullopt;
  return t->seconds;
}

std::optional<Timestamp> parse_formatted(std::string_view text, std::string_view format) {
  Fields x;
  std::size_t pos = 0;
  if (!match(text, pos, format, x) || pos != text.size()) return std::nullopt;
  if (x.pm >= 0) {
    if (x.hour < 1 || x.hour > 12) return std::nullopt;
    x.hour = x.hour % 12 + (x.pm == 1 ? 12U : 0U);
  }
  if (x.year < 0 || x.month < 1 || x.month > 12 || x.day < 1 ||
      x.day > days_in_month(x.year, x.month) || x.hour > 23 || x.minute > 59 || x.second > 60) {
    return std::nullopt;
  }
  const std::int64_t days = days_from_civil(x.year, x.month, x.day);
  const double seconds = static_cast<double>(days) * 86400.0 + x.hour * 3600.0 + x.minute * 60.0 +
                         x.second + x.fraction - x.offset_min * 60.0;
  return Timestamp{seconds, x.zoned};
}

std::string check_time_format(std::string_view format) {
  bool year = false, month = false, day = false, hour = false, hour12 = false, pm = false;
  for (std::size_t i = 0; i < format.size(); ++i) {
    if (format[i] != '%') continue;
    if (i + 1 == format.size()) return "a '%' at the end";
    const char d = format[++i];
    switch (d) {
      case 'Y':
      case 'y':
        year = true;
        break;
      case 'm':
      case 'b':
      case 'B':
      case 'h':
        month = true;
        break;
      case 'd':
      case 'e':
        day = true;
        break;
      case 'H':
        hour = true;
        break;
      case 'I':
        hour12 = true;
        break;
      case 'p':
        pm = true;
        break;
      case 'F':
        year = month = day = true;
        break;
      case 'T':
        hour = true;
        break;
      case 'M':
      case 'S':
      case 'z':
      case '%':
        break;
      default:
        return std::string("the directive %") + d + " is not supported";
    }
  }
  if (hour12 != pm) return "%I (12-hour clock) and %p (AM/PM) go together";
  if (!year || !month || !day) return "no year, month or day (%Y or %y, %m or %b, %d)";
  if (!hour && !hour12) return "no hour (%H, or %I with %p)";
  return "";
}

std::string format_utc(double seconds) {
  const auto whole = static_cast<std::int64_t>(std::floor(seconds));
  const std::int64_t days = (whole >= 0 ? whole : whole - 86399) / 86400;
  const std::int64_t rem = whole - days * 86400;
  std::int64_t y = 0;
  unsigned m = 0, d = 0;
  civil_from_days(days, y, m, d);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04lld-%02u-%02uT%02lld:%02lld:%02lldZ",
                static_cast<long long>(y), m, d, static_cast<long long>(rem / 3600),
                static_cast<long long>(rem / 60 % 60), static_cast<long long>(rem % 60));
  return buf;
}

}  // namespace excite::host::historian
