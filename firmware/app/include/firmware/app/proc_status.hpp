// SPDX-License-Identifier: MIT
#pragma once
// The process's resident memory, for the gateway's start-up and summary lines.

#include <string>

namespace excite::app {

/// "VmRSS 10188 kB, VmHWM 10188 kB" from /proc/self/status ("" where unavailable).
std::string memory_status();

}  // namespace excite::app
