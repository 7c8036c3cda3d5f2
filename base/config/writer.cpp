// SPDX-License-Identifier: MIT
#include "base/config/writer.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace excite::config {

std::string toml_number(double x) {
  char buffer[40];
  for (int digits = 1; digits <= 17; ++digits) {  // the shortest text that reads back as x
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  std::string s(buffer);
  // A whole number a person would write out ("120.0", not "1.2e+02"); exact below 2^53.
  if (s.find_first_of("eE") != std::string::npos && std::abs(x) < 0x1p53 && x == std::trunc(x)) {
    std::snprintf(buffer, sizeof buffer, "%.1f", x);
    s = buffer;
  }
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "n": nan/inf never written
  return s;
}

// A host with a quote or a newline once made gateway.toml invalid TOML: every control
// character is escaped.
std::string toml_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (byte < 0x20 || byte == 0x7f) {
          char code[8];
          std::snprintf(code, sizeof code, "\\u%04X", byte);
          out += code;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

}  // namespace excite::config
