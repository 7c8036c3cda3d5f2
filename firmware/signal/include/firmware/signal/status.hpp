// SPDX-License-Identifier: MIT
#pragma once
// The firmware core's status is the project's one status vocabulary
// (base/status/status.hpp); these names keep signal's and plan's code as it was.

#include "base/status/status.hpp"

namespace excite::signal {

using excite::Status;
using excite::StatusCode;
using excite::to_string;

}  // namespace excite::signal
