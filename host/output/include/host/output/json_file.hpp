// SPDX-License-Identifier: MIT
#pragma once
// A JSON file as the commands read it: a syntax error or a number beyond double's range
// (1e400) is told in the one message form, `FILE:LINE: FIELD = VALUE, expected WHAT`, with
// the line and the offending text, never the JSON library's bare message.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "host/output/input_file.hpp"

namespace excite::host {

namespace detail {
// The library's DOM builder, with the position and text of the first error kept.
class PositionedDom : public nlohmann::detail::json_sax_dom_parser<nlohmann::json> {
 public:
  explicit PositionedDom(nlohmann::json& j)
      : nlohmann::detail::json_sax_dom_parser<nlohmann::json>(j, false) {}
  template <class Exception>
  bool parse_error(std::size_t byte, const std::string& token, const Exception& e) {
    failed = true;
    at_byte = byte;
    last_token = token;
    overflow = e.id == 406;
    return false;
  }
  bool failed = false, overflow = false;
  std::size_t at_byte = 0;
  std::string last_token;
};

inline std::string short_text(const std::string& token) {
  std::string out;
  for (const char c : token.substr(0, 40)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return token.size() > 40 ? out + "…" : out;
}
}  // namespace detail

/// The largest JSON file a command reads: a model of 64 × 64 elements with every covariance
/// is about 15 MB; its parse takes about 20 bytes of memory per byte of text (a 60 MB file
/// once took 1.28 GB).
inline constexpr std::uintmax_t kMaxJsonFileBytes = std::uintmax_t{32} << 20;

/// Parses `path` as JSON; throws std::invalid_argument "PATH:LINE: …, expected …". The file
/// must be a regular file of at most kMaxJsonFileBytes (host/output/input_file.hpp: a FIFO or
/// /dev/zero is refused, naming the file).
inline nlohmann::json read_json_file(const std::string& path, const std::string& what) {
  const std::string text = read_input_file(path, kMaxJsonFileBytes, what);
  nlohmann::json j;
  detail::PositionedDom dom(j);
  const bool ok = nlohmann::json::sax_parse(text, &dom, nlohmann::json::input_format_t::json,
                                            /*strict=*/true);
  if (ok && !dom.failed) return j;
  const std::size_t end = std::min(dom.at_byte, text.size());
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(
                                   text.begin(), text.begin() + static_cast<long>(end), '\n'));
  const std::string where = path + ":" + std::to_string(line) + ": ";
  if (dom.overflow) {
    throw std::invalid_argument(where + "number = " + detail::short_text(dom.last_token) +
                                ", expected a number within ±1.8e308 (" + what + ")");
  }
  throw std::invalid_argument(where + "text = '" + detail::short_text(dom.last_token) +
                              "', expected JSON (" + what + ")");
}

}  // namespace excite::host
