// SPDX-License-Identifier: MIT
#include "base/config/check.hpp"

#include "base/config/error.hpp"

namespace excite::config {

std::string Check::message() const {
  if (ok()) return "ok";
  return format_message({}, Position{}, field, value, expected);
}

}  // namespace excite::config
