// SPDX-License-Identifier: MIT
#pragma once
// The one message form of every configuration error in the project:
//
//   FILE:LINE:COL: FIELD = VALUE, expected WHAT
//
// FIELD is the dotted path of the key ("registers.setpoints[1].address"), VALUE the value
// found as written (strings quoted, "(missing)" for an absent key, "(a table)", "(an
// array)"), WHAT what would have been accepted. LINE:COL is omitted where the position is
// not known (a check across several keys made after reading), FILE where the reader was
// given no source name. A TOML syntax error reads "FILE:LINE:COL: <parser's description>".

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "base/config/check.hpp"

namespace excite::config {

/// A place in a configuration text; line 0 means unknown.
struct Position {
  std::uint32_t line = 0;
  std::uint32_t column = 0;
};

/// Formats the one message form (see above).
std::string format_message(std::string_view source, Position at, std::string_view field,
                           std::string_view value, std::string_view expected);

/// A configuration error. what() is the full message; the parts stay readable so a caller
/// can add the source it knows (`with_source`) or rename a field.
class Error : public std::invalid_argument {
 public:
  /// A field error whose source and position are not known here.
  Error(std::string field, std::string value, std::string expected);
  /// A field error at a known place.
  Error(std::string_view source, Position at, std::string field, std::string value,
        std::string expected);
  /// The thrown form of a failed check (check.hpp): its field, value and expected, no place.
  explicit Error(const Check& failed);
  /// A free-text error (a TOML syntax error, an unreadable file): "FILE:LINE:COL: TEXT".
  static Error text(std::string_view source, Position at, std::string_view description);

  const std::string& source() const noexcept { return source_; }
  Position position() const noexcept { return at_; }
  const std::string& field() const noexcept { return field_; }
  const std::string& value() const noexcept { return value_; }
  const std::string& expected() const noexcept { return expected_; }

  /// The same error naming `source` if it named none.
  Error with_source(std::string_view source) const;

 private:
  Error(const std::string& message, std::string_view source, Position at, const std::string& field,
        const std::string& value, const std::string& expected);

  std::string source_;
  Position at_;
  std::string field_;  // empty for a free-text error
  std::string value_;
  std::string expected_;
};

}  // namespace excite::config
