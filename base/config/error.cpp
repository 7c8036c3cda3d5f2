// SPDX-License-Identifier: MIT
#include "base/config/error.hpp"

namespace excite::config {
namespace {

std::string prefix(std::string_view source, Position at) {
  std::string out(source);
  if (at.line != 0) {
    out += ":" + std::to_string(at.line) + ":" + std::to_string(at.column);
  }
  if (!out.empty()) out += ": ";
  return out;
}

}  // namespace

std::string format_message(std::string_view source, Position at, std::string_view field,
                           std::string_view value, std::string_view expected) {
  std::string out = prefix(source, at);
  out.append(field).append(" = ").append(value).append(", expected ").append(expected);
  return out;
}

Error::Error(const std::string& message, std::string_view source, Position at,
             const std::string& field, const std::string& value, const std::string& expected)
    : std::invalid_argument(message),
      source_(source),
      at_(at),
      field_(field),
      value_(value),
      expected_(expected) {}

Error::Error(std::string field, std::string value, std::string expected)
    : Error(std::string_view{}, Position{}, std::move(field), std::move(value),
            std::move(expected)) {}

Error::Error(std::string_view source, Position at, std::string field, std::string value,
             std::string expected)
    : Error(format_message(source, at, field, value, expected), source, at, field, value,
            expected) {}

Error::Error(const Check& failed) : Error(failed.field, failed.value, failed.expected) {}

Error Error::text(std::string_view source, Position at, std::string_view description) {
  return Error(prefix(source, at) + std::string(description), source, at, {}, {},
               std::string(description));
}

Error Error::with_source(std::string_view source) const {
  if (!source_.empty()) return *this;
  if (field_.empty()) return text(source, at_, expected_);
  return Error(source, at_, field_, value_, expected_);
}

}  // namespace excite::config
