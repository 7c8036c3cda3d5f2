// SPDX-License-Identifier: MIT
#pragma once

#include <string>
#include <utility>

namespace excite::hal {

// The result of checking a configuration (register map, frame map, device). Produced at
// configuration time only, so it may allocate; the cyclic path never builds one.
// A failure names the field (e.g. "values[2].address"), the offending value and what was
// expected, so the engineer can fix the file without reading code.
struct Validation {
  std::string field;     // empty when the configuration is valid
  std::string value;     // the offending value, as written
  std::string expected;  // what would have been accepted

  static Validation valid() { return {}; }
  static Validation invalid(std::string field_name, std::string offending, std::string wanted) {
    return {std::move(field_name), std::move(offending), std::move(wanted)};
  }

  [[nodiscard]] bool ok() const noexcept { return field.empty(); }

  // "<field> = <value>, expected <expected>" (the one message form,
  // base/status/status.hpp), or "ok".
  [[nodiscard]] std::string message() const {
    if (ok()) {
      return "ok";
    }
    return field + " = " + value + ", expected " + expected;
  }
};

}  // namespace excite::hal
