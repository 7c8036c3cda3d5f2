// SPDX-License-Identifier: MIT
#pragma once
// Run-log writer (format: firmware/runlog/README.md). No exceptions and no allocation:
// every function formats into a caller-provided buffer and reports by status, so the
// gateway's non-real-time log thread and `excite simulate` share exactly this code.
// Numbers are written with std::to_chars in shortest round-trip form: reading a row back
// gives the identical doubles.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string_view>

#include "base/status/status.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::runlog {

/// A closed-loop run (v4, README "Version 4"): the header keys `# loop: closed`,
/// `# excitation:`, `# controller:` and the columns r_*, uc_*, ysp_*, st_*, mode.
struct ClosedLoopHeader {
  bool closed = false;  // false: an open-loop run, written as v3 (nothing below is used)
  Excitation excitation = Excitation::setpoint;
  std::string_view controller;  // `<kind> <free text>`, one line, e.g. "dmc examples/a.toml"
  /// The channels r was added to, ascending: output indices for `setpoint`, input indices
  /// for `mv`, for `both` output indices 0 … p − 1 then p + input index (at least one; each
  /// once).
  std::span<const std::size_t> r_channels;
};

/// What the comment header says about the run.
struct Header {
  std::string_view plant;        // free text, one line (no CR/LF)
  std::string_view plan;         // free text, one line (no CR/LF), e.g. the plan file path
  double sample_time_min = 0.0;  // T, minutes, finite and > 0
  std::span<const Channel> inputs;
  std::span<const Channel> outputs;
  std::string_view producer = {};     // program and version, one line, e.g. "excite-gateway 0.1.0";
                                      // written as `# producer:` when not empty (every excite
                                      // producer sets it)
  TimeScales time_scales = {};        // each written when > 0 (finite and ≥ 0)
  std::string_view baseline = {};     // how the baselines were taken, one line; `# baseline:`
                                      // when not empty (excite import)
  bool start_at_rest = true;          // false: `# start_at_rest: no` — the record starts
                                      // mid-test, identify estimates the initial state
  ClosedLoopHeader closed_loop = {};  // closed: the log is v4
};

/// One sample. du, u have one value per input, dy one per output; all finite.
/// A producer without a fresh measurement repeats the last value and sets kCommLost/kStale.
struct Row {
  double t_min = 0.0;                  // time since the start of the run, minutes
  std::uint64_t k = 0;                 // sample index
  std::span<const double> du;          // input deviations from the baseline
  std::span<const double> u;           // absolute inputs (baseline + du), engineering units
  std::span<const double> dy;          // output deviations from the baseline
  std::uint32_t flags = 0;             // bits of Flag only (kKnownFlags)
  RunState state = RunState::unknown;  // the engine's state at this row (v2 `state` column)
  std::uint32_t segment = 0;           // plan segment of this row (v3 `segment` column)
  // v4 only (a closed-loop header), deviations from the baseline in engineering units:
  std::span<const double> r = {};    // the test signal, one per header r channel
  std::span<const double> uc = {};   // the controller's output before the dither and any clamp
  std::span<const double> ysp = {};  // the CV setpoints in force, one per output
  std::span<const MvState> st = {};  // each MV's status, one per input
  LoopMode mode = LoopMode::test;    // the loop's mode at this row
};

/// The writer's status is the project's one vocabulary (base/status/status.hpp):
///   ok                 written
///   capacity_exceeded  the buffer is too small; nothing usable was written
///   invalid_field      a header field: plant/plan/producer text with CR or LF, a channel
///                      name or unit invalid or repeated, sample_time_min not finite or <= 0
///   bad_argument       a row: du/u/dy widths differ from the header's channel counts, a
///                      number is NaN or inf, or flags has bits outside kKnownFlags
///   io_error           fwrite to the FILE* failed
/// WriteResult::message says which, in the one form "FIELD = VALUE, expected WHAT".
using WriteStatus = excite::StatusCode;

/// Short English description of a status, for log messages.
std::string_view describe(WriteStatus status);

struct WriteResult {
  WriteStatus status = WriteStatus::ok;
  std::size_t length = 0;    // characters written to the buffer (no terminating NUL), if ok
  const char* message = "";  // static text naming the field at fault, "" if ok
};

/// Formats the comment header and the column header row into `out`.
WriteResult format_header(const Header& header, std::span<char> out);

/// Formats one data row (with its newline) into `out`. `out.size() >=
/// max_row_chars(inputs, outputs)` always suffices (a closed-loop header:
/// max_closed_loop_row_chars). The header is used for channel counts.
WriteResult format_row(const Header& header, const Row& row, std::span<char> out);

/// Writes a run log to an open FILE* through a caller-provided buffer (no allocation).
/// The caller owns the FILE* (opens, flushes, closes it) and the buffer, which must
/// outlive the writer.
class FileWriter {
 public:
  FileWriter(std::FILE* file, const Header& header, std::span<char> buffer)
      : file_(file), header_(header), buffer_(buffer) {}

  WriteStatus write_header();
  WriteStatus write_row(const Row& row);
  /// What the last non-ok call refused, in the one message form ("" after ok).
  const char* detail() const { return detail_; }

 private:
  WriteStatus emit(WriteResult result);

  const char* detail_ = "";
  std::FILE* file_;
  Header header_;
  std::span<char> buffer_;
};

}  // namespace excite::runlog
