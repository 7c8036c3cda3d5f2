// SPDX-License-Identifier: MIT
#pragma once
// excite-gateway's exit codes (README.md, "Exit codes": one table). When several apply,
// the field's state comes first: hard_stop, then unconfirmed, then the fault that stopped the
// excitation (fault, device_refused), then log_fault,
// then the log's other codes (7, 8), then aborted, then ok.

namespace excite::app {

enum class ExitCode : int {
  ok = 0,               // the table was streamed completely and the field is back at baseline
                        // (or --dry-run: every check passed)
  usage = 1,            // bad command line
  bad_config = 2,       // the configuration file is missing or invalid (register map included)
  bad_plan = 3,         // the plan file is unreadable, corrupt, for another configuration, or
                        // its table leaves the plan's limits
  device = 4,           // the field device is unreachable (connect failed)
  arm_refused = 5,      // the live values refuse arming (baseline outside limits, read failed,
                        // or another master writing: a readback or the echo moved before arm)
  aborted = 6,          // aborted (operator: SIGTERM, stdin, command register; or a suspension
                        // timeout) and the baseline was written and read back (confirmed)
  log_error = 7,        // the run log cannot be opened or written
  log_incomplete = 8,   // the log ring overran: ticks are missing from the log (counted)
  hard_stop = 9,        // the ramp-out was cut short (a second SIGTERM/SIGINT): the field may
                        // be left excited; the log is complete up to the last tick
  unconfirmed = 10,     // safe, unconfirmed: the baseline was written but never read back
                        // (link down, or readbacks disagreeing) — the field's state is unknown
  fault = 11,           // a fault stopped the excitation (verified writes: a readback disagreed
                        // with the setpoint written; or another writer was seen); the baseline
                        // was confirmed afterwards
  distorted = 12,       // refused (dry run or arm, before any excitation): the plan would be
                        // clamped or rate-limited on more than gateway.max_distortion of a
                        // channel's rows (--allow-distortion overrides)
  log_fault = 13,       // a run-log write failed mid-run (disk full, file-size limit, I/O
                        // error): the excitation stopped, ramped out, and the baseline was
                        // confirmed; the log is whole up to its last full row
  device_refused = 14,  // the device refused a request (exception reply 1, 2 or 3: illegal
                        // function, data address, data value): the excitation stopped at
                        // once, ramped out, and the baseline was confirmed
};

}  // namespace excite::app
