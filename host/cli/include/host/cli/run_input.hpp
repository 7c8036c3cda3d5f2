// SPDX-License-Identifier: MIT
#pragma once
// Run logs as the commands read them: a clear error naming file, line and column, or the
// data with its channel names. Limits (host/README.md, "Limits"), checked before the work:
// at most kMaxRunRows data rows (counted while streaming the file, before it is loaded),
// every du/dy value within ±kMaxRunValue (so sums of squares cannot overflow to inf/NaN).

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "host/output/input_path.hpp"
#include "host/identify/run_data.hpp"

namespace excite::host::cli {

inline constexpr std::size_t kMaxRunRows = 100'000;
inline constexpr double kMaxRunValue = 1e12;

struct Run {
  runlog::RunLog log;
  RunData data;
};

/// Data rows of a run log (lines neither blank nor `#` comments, less the column header),
/// counted in fixed memory; returns as soon as more than `limit` are seen (then limit + 1).
inline std::size_t count_run_rows(const std::string& path, std::size_t limit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;  // the reader names the error
  char buffer[1 << 16];
  std::size_t lines = 0;
  bool at_line_start = true;
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      const char c = buffer[i];
      if (at_line_start && c != '#' && c != '\n' && c != '\r') ++lines;
      at_line_start = c == '\n';
      if (lines > limit + 1) return limit + 1;  // + 1: the column header row
    }
  }
  return lines == 0 ? 0 : lines - 1;
}

/// Throws once more than kMaxRunRows data rows are seen in the run log.
inline void check_run_rows(const std::string& path) {
  if (count_run_rows(path, kMaxRunRows) > kMaxRunRows) {
    throw std::invalid_argument(path + ": more than " + std::to_string(kMaxRunRows) +
                                " data rows, expected at most " + std::to_string(kMaxRunRows) +
                                " (host/README.md, Limits)");
  }
}

/// Every deviation value within ±kMaxRunValue; the error names file, row, column and value.
inline void check_run_values(const std::string& path, const runlog::RunLog& log) {
  const auto check = [&](const std::vector<std::vector<double>>& columns,
                         const std::vector<std::string>& names, const char* prefix) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      for (std::size_t r = 0; r < columns[c].size(); ++r) {
        const double v = columns[c][r];
        if (std::isfinite(v) && std::fabs(v) <= kMaxRunValue) continue;
        char text[120];
        std::snprintf(text, sizeof text, "data row %zu (k = %llu), column %s", r + 1,
                      static_cast<unsigned long long>(log.k[r]), prefix);
        char value[80];
        std::snprintf(value, sizeof value, " = %.6g, expected |value| <= %g", v, kMaxRunValue);
        throw std::invalid_argument(path + ": " + text + names[c] + value);
      }
    }
  };
  check(log.du, log.input_names, "du_");
  check(log.dy, log.output_names, "dy_");
}

/// The log as read, with the size and value checks, without run_data(): the commands that
/// apply the flags rule (identify, validate, balance) take rows flagged skipped or
/// discontinuity as segment starts, which run_data() refuses.
inline runlog::RunLog read_log(const std::string& path) {
  refuse_directory(path, "a run log (CSV)");
  check_run_rows(path);
  runlog::ReadResult r = runlog::read_run_log(path);
  if (!r.ok()) throw std::invalid_argument(r.error->to_string());
  check_run_values(path, r.log);
  return std::move(r.log);
}

inline Run read_run(const std::string& path) {
  Run run{read_log(path), {}};
  run.data = run_data(run.log);
  return run;
}

}  // namespace excite::host::cli
