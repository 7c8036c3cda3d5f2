// SPDX-License-Identifier: MIT
#pragma once
// excite-gateway's exit codes (README.md).

namespace excite::app {

enum class ExitCode : int {
  ok = 0,              // the table was streamed completely and the field is back at baseline
                       // (or --dry-run: every check passed)
  usage = 1,           // bad command line
  bad_config = 2,      // the configuration file is missing or invalid (register map included)
  bad_plan = 3,        // the plan file is unreadable, corrupt, for another configuration, or
                       // its table leaves the plan's limits
  device = 4,          // the field device is unreachable (connect failed)
  arm_refused = 5,     // the live values refuse arming (baseline outside limits, read failed)
  aborted = 6,         // the run was aborted (operator, SIGTERM, suspension timeout, hard stop);
                       // the log is complete up to the last tick
  log_error = 7,       // the run log cannot be opened or written
  log_incomplete = 8,  // the log ring overran: ticks are missing from the log (counted)
};

}  // namespace excite::app
