// SPDX-License-Identifier: MIT
#pragma once
// The one status vocabulary of the firmware and the hal (STYLE.md practice 6): one code
// enum, one status value with a message, one message form. firmware/signal and
// firmware/plan return `Status`; the hal returns a bare `StatusCode` from its cyclic calls
// (hal::Status is this enum; its contract per code is in hal/include/excite/hal/status.hpp);
// the run-log writer returns a `StatusCode` in its WriteResult.
//
// The message form, everywhere (firmware, hal, configuration files):
//   FIELD = VALUE, expected WHAT
// e.g. "sources[2].prbs.register_length = 40, expected 2…31". A configuration file's
// reader (base/config) puts "FILE:LINE:COL: " in front.
//
// Contract: a Status is either ok (code() == StatusCode::ok, message() == "") or an error
// whose message() is in the form above. The message lives in a fixed buffer inside the
// value (no heap), is always NUL-terminated and is cut at kMessageCapacity − 1 bytes.
// Nothing here allocates or throws: usable on the gateway's cyclic path.

#include <array>
#include <cstdarg>
#include <cstddef>
#include <cstdint>

namespace excite {

enum class StatusCode : std::uint8_t {
  ok = 0,
  // Content: what was read or given is not what its contract allows.
  invalid_field,        // a field has a value outside its contract (the message names it)
  capacity_exceeded,    // a count or size is beyond a fixed or caller-given capacity
  truncated,            // input bytes end before the structure does
  bad_magic,            // the input is not a plan file
  checksum_mismatch,    // the stored CRC-32 differs from the computed one
  unsupported_version,  // the file's format version is not one this build reads
  limit_violated,       // a table value lies outside its channel's deviation limits
  bad_argument,         // caller error (wrong span size, non-finite value); nothing was done
  // Transport and I/O (hal, the run-log writer): the operation did not complete.
  timeout,      // the peer did not answer in time
  link_lost,    // the connection dropped or could not be re-established
  peer_error,   // the peer answered with an error or a malformed reply
  unavailable,  // the transport cannot work here (not configured, no kernel support)
  io_error,     // a write to a file failed
};

/// Short lower-case name of a code ("ok", "invalid_field", "timeout", …), for logs.
constexpr const char* to_string(StatusCode code) noexcept {
  switch (code) {
    case StatusCode::ok:
      return "ok";
    case StatusCode::invalid_field:
      return "invalid_field";
    case StatusCode::capacity_exceeded:
      return "capacity_exceeded";
    case StatusCode::truncated:
      return "truncated";
    case StatusCode::bad_magic:
      return "bad_magic";
    case StatusCode::checksum_mismatch:
      return "checksum_mismatch";
    case StatusCode::unsupported_version:
      return "unsupported_version";
    case StatusCode::limit_violated:
      return "limit_violated";
    case StatusCode::bad_argument:
      return "bad_argument";
    case StatusCode::timeout:
      return "timeout";
    case StatusCode::link_lost:
      return "link_lost";
    case StatusCode::peer_error:
      return "peer_error";
    case StatusCode::unavailable:
      return "unavailable";
    case StatusCode::io_error:
      return "io_error";
  }
  return "unknown";
}

class [[nodiscard]] Status {
 public:
  static constexpr std::size_t kMessageCapacity = 192;

  /// The ok status.
  constexpr Status() = default;

  /// An error with a printf-style message in the form "FIELD = VALUE, expected WHAT".
  /// `code` must not be StatusCode::ok (it is taken as invalid_field).
  static Status error(StatusCode code, const char* format, ...)
      __attribute__((format(printf, 2, 3)));
  /// As error(), with the arguments as a va_list (for wrappers of error()).
  static Status error_v(StatusCode code, const char* format, va_list args)
      __attribute__((format(printf, 2, 0)));
  /// An error from its three parts: "FIELD = VALUE, expected WHAT".
  static Status field_error(StatusCode code, const char* field, const char* value,
                            const char* expected);

  bool is_ok() const { return code_ == StatusCode::ok; }
  explicit operator bool() const { return is_ok(); }
  StatusCode code() const { return code_; }
  const char* message() const { return message_.data(); }

 private:
  StatusCode code_ = StatusCode::ok;
  std::array<char, kMessageCapacity> message_{};
};

}  // namespace excite
