// SPDX-License-Identifier: MIT
#include "host/import/number_text.hpp"

#include <charconv>
#include <cmath>
#include <string>

namespace excite::host::historian {
namespace {

bool digit(char c) {
  return c >= '0' && c <= '9';
}

// The integer part [b, e) with grouping separators removed into `out`; false when the
// grouping is not 1–3 digits then groups of exactly 3.
bool ungroup(std::string_view s, char group, std::string& out) {
  if (s.find(group) == std::string_view::npos) {
    out.append(s);
    return true;
  }
  std::size_t first = s.find(group);
  if (first == 0 || first > 3) return false;
  std::size_t pos = 0;
  while (pos < s.size()) {
    const std::size_t next = s.find(group, pos);
    const std::size_t end = next == std::string_view::npos ? s.size() : next;
    const std::size_t len = end - pos;
    if (pos > 0 && len != 3) return false;
    for (std::size_t i = pos; i < end; ++i) {
      if (!digit(s[i])) return false;
    }
    out.append(s.substr(pos, len));
    if (next == std::string_view::npos) break;
    pos = next + 1;
    if (pos == s.size()) return false;  // a trailing separator
  }
  return true;
}

}  // namespace

std::optional<double> parse_number(std::string_view text, bool decimal_comma) {
  if (text.empty()) return std::nullopt;
  const char point = decimal_comma ? ',' : '.';
  const char group = decimal_comma ? '.' : ',';
  std::string plain;
  std::size_t pos = 0;
  if (text[0] == '+' || text[0] == '-') {
    if (text[0] == '-') plain += '-';
    pos = 1;
  }
  // The integer part runs to the decimal separator or the exponent.
  std::size_t int_end = pos;
  while (int_end < text.size() && (digit(text[int_end]) || text[int_end] == group)) ++int_end;
  if (!ungroup(text.substr(pos, int_end - pos), group, plain)) return std::nullopt;
  std::string_view rest = text.substr(int_end);
  if (!rest.empty() && rest[0] == point) {
    plain += '.';
    rest.remove_prefix(1);
  }
  for (const char c : rest) {
    if (c == group || c == point) return std::nullopt;
    plain += c;
  }
  double v = 0.0;
  const char* b = plain.data();
  const char* e = b + plain.size();
  const auto [end, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || end != e || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace excite::host::historian
