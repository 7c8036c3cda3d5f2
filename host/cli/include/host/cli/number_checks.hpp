// SPDX-License-Identifier: MIT
#pragma once
// CLI11 validators shared by every `excite` option that takes a real number. CLI11's own
// PositiveNumber/NonNegativeNumber let "nan" through (every comparison with NaN is false);
// these refuse NaN, infinities and out-of-range values, and CLI11 prefixes the option's
// name: "--noise-var: nan, expected a finite number >= 0".

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

namespace excite::host::cli {

/// A finite number x with x > lowest (strict) or x >= lowest; `expected` is the message's
/// "expected …" text.
inline CLI::Validator finite_number(double lowest, bool strict, const std::string& expected) {
  return CLI::Validator(
      [lowest, strict, expected](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && end != nullptr && *end == '\0';
        if (parsed && std::isfinite(x) && (strict ? x > lowest : x >= lowest)) return "";
        return text + ", expected " + expected;
      },
      expected);
}

inline CLI::Validator finite_positive() {
  return finite_number(0.0, true, "a finite number > 0");
}
inline CLI::Validator finite_non_negative() {
  return finite_number(0.0, false, "a finite number >= 0");
}

}  // namespace excite::host::cli
