// SPDX-License-Identifier: MIT
#pragma once
// Numbers in messages in short form: a user's 310-digit number (or CLI11's echo of it) is
// shown as "1e+309" — or, when it is not a number double can hold, its first digits and
// its length — so a message stays one line that names the value.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace excite::host::cli {

/// `text` with every run of number characters ([0-9.eE+-], at least one digit) longer than
/// 24 characters replaced by its short form.
inline std::string short_numbers(const std::string& text) {
  const auto is_number_char = [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-';
  };
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    if (!is_number_char(text[i])) {
      out += text[i++];
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && is_number_char(text[end])) ++end;
    const std::string run = text.substr(i, end - i);
    i = end;
    if (run.size() <= 24 || run.find_first_of("0123456789") == std::string::npos) {
      out += run;
      continue;
    }
    char* stop = nullptr;
    const double x = std::strtod(run.c_str(), &stop);
    char shown[64];
    if (stop == run.c_str() + run.size() && std::isfinite(x)) {
      std::snprintf(shown, sizeof shown, "%.6g", x);
    } else {
      std::snprintf(shown, sizeof shown, "%.12s… (%zu characters)", run.c_str(), run.size());
    }
    out += shown;
  }
  return out;
}

}  // namespace excite::host::cli
