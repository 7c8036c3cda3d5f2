// SPDX-License-Identifier: MIT
#pragma once
// Run-log reader (format: firmware/runlog/README.md). No exceptions: the result carries
// either the columns or one error naming file, line, column and what was expected.
// Runs on the host and the gateway's non-real-time side; it allocates.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/runlog/format.hpp"

namespace excite::runlog {

/// What a v4 (closed-loop) log adds (README "Version 4"); empty for v1–v3 logs.
struct ClosedLoopLog {
  bool closed = false;  // true for a v4 log (`# loop: closed`)
  Excitation excitation = Excitation::setpoint;
  std::string controller;                // the `# controller:` line ("dmc …", "pi …")
  std::vector<std::size_t> r_channels;   // the channels r was added to: output indices
                                         // (setpoint), input indices (mv); both: outputs
                                         // 0 … p − 1, then p + input index; ascending
  std::vector<std::vector<double>> r;    // one column per r channel, in r_channels' order
  std::vector<std::vector<double>> uc;   // per input: the controller's output
  std::vector<std::vector<double>> ysp;  // per output: the setpoint in force
  std::vector<std::vector<MvState>> st;  // per input: MV status
  std::vector<LoopMode> mode;
};

/// A run log in columns. du[i], u[i] are input i's columns, dy[j] output j's, each with
/// rows() values; t_min, k, flags, state likewise.
struct RunLog {
  int format_version = 3;  // 1, 2, 3 or 4: the magic line's version
  std::string producer;    // the `# producer:` line ("excite-gateway 0.1.0"); "" when absent
  std::string plant;
  std::string plan;
  double sample_time_min = 0.0;
  TimeScales time_scales;     // the optional `# tau_high_min:`, `# beta:`, `# switch_time_min:`
                              // lines; 0 where absent (not known)
  std::string baseline;       // the `# baseline:` line (how import took them); "" when absent
  bool start_at_rest = true;  // false when the log says `# start_at_rest: no`
  std::vector<std::string> input_names, input_units;
  std::vector<std::string> output_names, output_units;

  std::vector<double> t_min;
  std::vector<std::uint64_t> k;
  std::vector<std::vector<double>> du, u, dy;
  std::vector<std::uint32_t> flags;
  std::vector<RunState> state;         // v2: the `state` column; v1: RunState::unknown on every row
  std::vector<std::uint32_t> segment;  // v3: the `segment` column; v1, v2: 0 on every row
  ClosedLoopLog closed_loop;           // v4: r, uc, ysp, st, mode; empty (closed = false) before

  std::size_t rows() const { return t_min.size(); }
};

/// Where and why a log was rejected. line and column are 1-based (0: not applicable);
/// column counts comma-separated fields.
struct ReadError {
  std::string file;
  std::size_t line = 0;
  std::size_t column = 0;
  std::string message;

  /// "file:line: column c (name): message", the form every tool prints.
  std::string to_string() const;
};

struct ReadOptions {
  std::size_t min_rows = 2;  // fewer data rows is an error
  // Time stamps must be uniform: k[r] = k[r−1] + 1 and |t_min[r] − t_min[r−1] − T| ≤
  // time_tolerance · T (T = sample_time_min of the header). v2 only: a row flagged kSkipped
  // has k[r] > k[r−1] + 1 and |t_min[r] − t_min[r−1] − (k[r] − k[r−1])·T| ≤ time_tolerance · T.
  double time_tolerance = 1e-6;
  // Limits a reader sets once, so every read of a log holds to them (issue 38 §1):
  //   - more than max_rows data rows is an error, "more than N data rows, expected at most N";
  //     read_run_log counts while it reads and stops at the first row past the limit, so a
  //     log of 10⁷ rows costs memory for max_rows of them, never for the whole file;
  //   - a du or dy value with |value| > max_abs_value is an error naming the data row, its k
  //     and the column ("data row 3 (k = 2), column dy_y1 = 1e+308, expected |value| <= 1e+12").
  // `limits_source`, when set, ends the row limit's message as " (SOURCE)". Both errors have
  // line and column 0 (ReadError::to_string: "file: message").
  std::size_t max_rows = static_cast<std::size_t>(-1);  // default: no limit
  double max_abs_value = 0.0;                           // 0: no bound
  std::string limits_source;
};

struct ReadResult {
  RunLog log;                      // valid only when ok()
  std::optional<ReadError> error;  // set when the log was rejected
  bool over_row_limit = false;     // the error is ReadOptions::max_rows'
  bool ok() const { return !error.has_value(); }
};

/// Parses a whole log held in memory; `file_name` only labels errors. The row limit is
/// checked before the rows are parsed, the value bound after.
ReadResult parse_run_log(std::string_view text, std::string_view file_name,
                         const ReadOptions& options = {});

/// Reads and parses the file at `path`, opening it once; the row limit is checked while
/// reading, before anything is parsed.
ReadResult read_run_log(const std::string& path, const ReadOptions& options = {});

}  // namespace excite::runlog
