// SPDX-License-Identifier: MIT
#include "host/export/code_text.hpp"

#include <cstdio>
#include <stdexcept>

namespace excite::host {
namespace {

bool control(unsigned char byte) {
  return byte < 0x20 || byte == 0x7f;
}

std::string hex(unsigned char byte) {
  char text[8];
  std::snprintf(text, sizeof text, "\\x%02x", static_cast<unsigned>(byte));
  return text;
}

// Length of the UTF-8 sequence starting at s[i], or 0 when it is not one (overlong forms,
// surrogates and code points beyond U+10FFFF refused, as RFC 3629 says).
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = at(i);
  if (lead < 0x80) return 1;
  std::size_t n = 0;
  unsigned char low = 0x80, high = 0xbf;  // the second byte's range
  if (lead >= 0xc2 && lead <= 0xdf) {
    n = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    n = 3;
    if (lead == 0xe0) low = 0xa0;
    if (lead == 0xed) high = 0x9f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    n = 4;
    if (lead == 0xf0) low = 0x90;
    if (lead == 0xf4) high = 0x8f;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (at(i + 1) < low || at(i + 1) > high) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
  }
  return n;
}

}  // namespace

std::string comment_text(std::string_view value) {
  std::string out;
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    out += control(byte) ? hex(byte) : std::string(1, c);
  }
  return out;
}

std::string shown_text(std::string_view value) {
  const std::string text = comment_text(value.substr(0, 40));
  return value.size() > 40 ? text + "…" : text;
}

void require_utf8(const std::string& field, std::string_view value) {
  for (std::size_t i = 0; i < value.size();) {
    const std::size_t n = utf8_length(value, i);
    if (n == 0) {
      std::string bytes;  // shown with every byte beyond ASCII as \xNN
      for (const char c : value.substr(0, 40)) {
        const auto byte = static_cast<unsigned char>(c);
        bytes += control(byte) || byte >= 0x80 ? hex(byte) : std::string(1, c);
      }
      throw std::invalid_argument(field + " = \"" + bytes + (value.size() > 40 ? "…" : "") +
                                  "\" (byte " + std::to_string(i) + "), expected UTF-8 text");
    }
    i += n;
  }
}

std::string python_triple_quoted_body(std::string_view value, char quote) {
  std::string out;
  for (const char c : value) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\\' || c == quote) {
      out += '\\';
      out += c;
    } else if (c != '\n' && control(byte)) {
      out += hex(byte);
    } else {
      out += c;
    }
  }
  return out;
}

std::string matlab_string_literal(const std::string& field, std::string_view value) {
  std::string out = "'";
  for (const char c : value) {
    if (control(static_cast<unsigned char>(c))) {
      throw std::invalid_argument(field + " = \"" + shown_text(value) +
                                  "\", expected a name without control characters (a MATLAB "
                                  "string has no escape for them)");
    }
    out += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return out + "'";
}

}  // namespace excite::host
