// SPDX-License-Identifier: MIT
#pragma once
// The end of a run (README "End-of-run summary"): what the gateway reports once the engine
// is safe — how the run ended, the engine's and the transport's counts, the faults in
// words, the run log's fate — gathered into one struct, printed by one function, and the
// exit code decided from it (exit_codes.hpp: the field's state first, then the log's, then
// how the run ended). After the run: allocates.

#include <cstdint>
#include <cstdio>
#include <string>

#include "firmware/app/bus_factory.hpp"
#include "firmware/app/gateway.hpp"
#include "firmware/app/run_log_file.hpp"
#include "firmware/app/runner.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::app {

struct RunSummary {
  RunStats stats;
  bool cut_short = false;  // stopped before the baseline was reached (a second SIGTERM)
  std::uint64_t rows_logged = 0;
  // The engine's counts.
  std::uint64_t comm_losses = 0;
  std::uint64_t suspensions = 0;
  std::uint64_t readback_mismatches = 0;
  std::uint64_t ticks_skipped = 0;
  std::uint64_t stale_writes_undone = 0;
  bool acknowledge_command = false;  // the command register is cleared after each code
  std::uint64_t commands_acknowledged = 0;
  // Closed loop ([closed_loop]): episodes of the controller out of its mode and of an MV
  // clamped or wound up (each suspended the test).
  bool closed_loop = false;
  std::uint64_t controller_mode_losses = 0;
  std::uint64_t mv_limited = 0;
  // Rows of the run log per condition: what the log's flags say, counted as they were set.
  std::uint64_t rows_clamped = 0;
  std::uint64_t rows_rate_limited = 0;
  std::uint64_t rows_suspended = 0;
  std::uint64_t rows_comm_lost = 0;
  std::uint64_t rows_stale = 0;
  std::uint64_t rows_skipped = 0;
  std::uint64_t rows_discontinuity = 0;
  // [segments] await_s (0: no wait) and the rows that held the baseline awaiting a segment
  // (among rows_suspended; real time — lock-step waits without ticking, RunStats).
  double segment_await_s = 0.0;
  std::uint64_t rows_awaiting = 0;
  // In words ("": nothing to say).
  std::string bus_counts;      // the transport's own counts (Modbus: exception replies by code)
  std::string refusal;         // the device's refusal (Gateway::refusal_report)
  std::string readback_fault;  // the verified write that failed
  std::string foreign_write;   // another master's write (Gateway::foreign_write_report)
  std::string range_ends;      // values at the end of their register's range
  std::string memory;          // memory after the run (proc_status.hpp)
  double confirm_timeout_s = 0.0;
  // The run log.
  std::string log_path;
  std::string log_failure;  // a write that failed mid-run (Gateway::log_failure)
  runlog::WriteStatus log_status = runlog::WriteStatus::ok;
  bool log_closed = true;
};

/// After Gateway::run(): drains and joins the log thread, closes the log file, and gathers
/// the summary.
RunSummary finish_run(Gateway& gw, const RunStats& stats, const BusResult& made, RunLogFile& log);

/// The summary's lines on `out`, each starting "excite-gateway: ".
void print_summary(std::FILE* out, const RunSummary& s);

/// The exit code; with a message for the log's codes (7, 8, 13), "" for the others (the
/// summary has said it).
StageError verdict(const RunSummary& s);

}  // namespace excite::app
