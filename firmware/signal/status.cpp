// SPDX-License-Identifier: MIT
#include "firmware/signal/status.hpp"

#include <cstdarg>
#include <cstdio>

namespace excite::signal {

const char* to_string(StatusCode code) {
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
  }
  return "unknown";
}

Status Status::error_v(StatusCode code, const char* format, va_list args) {
  Status status;
  status.code_ = code == StatusCode::ok ? StatusCode::invalid_field : code;
  std::vsnprintf(status.message_.data(), status.message_.size(), format, args);
  return status;
}

Status Status::error(StatusCode code, const char* format, ...) {
  va_list args;
  va_start(args, format);
  Status status = error_v(code, format, args);
  va_end(args);
  return status;
}

}  // namespace excite::signal
