// SPDX-License-Identifier: MIT
#pragma once
// A configuration check's result: the non-throwing form of config::Error (error.hpp), for
// code that checks what a configuration says without throwing (hal's register and frame
// maps, its devices, the range a field encoding carries; hal's field buses are built without
// exceptions). A reader that throws turns a failed check into `config::Error(check)`.
// Made at configuration time only, so it may allocate; no cyclic path builds one.

#include <string>
#include <utility>

namespace excite::config {

struct Check {
  std::string field;     // empty when the check passed
  std::string value;     // the offending value, as written
  std::string expected;  // what would have been accepted

  static Check valid() { return {}; }
  static Check invalid(std::string field_name, std::string offending, std::string wanted) {
    return {std::move(field_name), std::move(offending), std::move(wanted)};
  }

  [[nodiscard]] bool ok() const noexcept { return field.empty(); }

  /// "FIELD = VALUE, expected WHAT" (format_message, the one form, without FILE:LINE:COL),
  /// or "ok".
  [[nodiscard]] std::string message() const;
};

}  // namespace excite::config
