// SPDX-License-Identifier: MIT
#pragma once
// The one status type of the firmware core (STYLE.md practice 6).
//
// Contract: a Status is either ok (code() == StatusCode::ok, message() == "") or an error
// whose message() names the field, the value found and what was expected, e.g.
// "sources[2].prbs.register_length = 40, expected 2…31". The message lives in a fixed
// buffer inside the value (no heap), is always NUL-terminated and is cut at
// kMessageCapacity − 1 bytes. Functions returning Status never throw.

#include <array>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

namespace excite::signal {

enum class StatusCode : std::uint8_t {
  ok = 0,
  invalid_field,        // a field of a recipe or plan has a value outside its contract
  capacity_exceeded,    // a count or size is beyond a fixed or caller-given capacity
  truncated,            // input bytes end before the structure does
  bad_magic,            // the input is not a plan file
  checksum_mismatch,    // the stored CRC-32 differs from the computed one
  unsupported_version,  // the file's format version is not one this build reads
  limit_violated,       // a table value lies outside its channel's deviation limits
};

/// Short lower-case name of a code ("ok", "invalid_field", …), for logs.
const char* to_string(StatusCode code);

class [[nodiscard]] Status {
 public:
  static constexpr std::size_t kMessageCapacity = 192;

  /// The ok status.
  constexpr Status() = default;

  /// An error with a printf-style message. `code` must not be StatusCode::ok.
  static Status error(StatusCode code, const char* format, ...)
      __attribute__((format(printf, 2, 3)));
  /// As error(), with the arguments as a va_list (for wrappers of error()).
  static Status error_v(StatusCode code, const char* format, va_list args)
      __attribute__((format(printf, 2, 0)));

  bool is_ok() const { return code_ == StatusCode::ok; }
  explicit operator bool() const { return is_ok(); }
  StatusCode code() const { return code_; }
  const char* message() const { return message_.data(); }

 private:
  StatusCode code_ = StatusCode::ok;
  std::array<char, kMessageCapacity> message_{};
};

}  // namespace excite::signal
