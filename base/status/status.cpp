// SPDX-License-Identifier: MIT
#include "base/status/status.hpp"

#include <cstdarg>
#include <cstdio>

namespace excite {

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

Status Status::field_error(StatusCode code, const char* field, const char* value,
                           const char* expected) {
  return error(code, "%s = %s, expected %s", field, value, expected);
}

}  // namespace excite
