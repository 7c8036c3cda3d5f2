// SPDX-License-Identifier: MIT
#pragma once
// Several run logs identified together (excite identify RUN…): the row limit holds for
// all of them together, counted by the reader as each is read, and runs are pooled only when their
// headers say they come from the same plant with the same units (host/README.md, Limits).

#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "host/cli/run_input.hpp"

namespace excite::host::cli {

/// Reads every run, each file opened once: at most kMaxRunRows data rows over all `paths`
/// together, enforced by the reader as it reads (each run may hold what the earlier ones
/// left); the run that crosses the limit is named with the count of runs.
inline std::vector<runlog::RunLog> read_pooled_logs(const std::vector<std::string>& paths) {
  if (paths.size() == 1) return {read_log(paths.front())};
  std::vector<runlog::RunLog> runs;
  std::size_t total = 0;
  for (const std::string& path : paths) {
    refuse_directory(path, "a run log (CSV)");
    runlog::ReadResult r =
        runlog::read_run_log(path, limited_read_options({}, kMaxRunRows - total));
    if (r.over_row_limit) {
      throw std::invalid_argument(
          path + ": more than " + std::to_string(kMaxRunRows) + " data rows in the " +
          std::to_string(paths.size()) + " runs together (counted up to this one), expected at " +
          "most " + std::to_string(kMaxRunRows) + " in total (host/README.md, Limits)");
    }
    if (!r.ok()) throw std::invalid_argument(r.error->to_string());
    total += r.log.rows();
    runs.push_back(std::move(r.log));
  }
  return runs;
}

namespace detail {
inline std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
  return out;
}
}  // namespace detail

/// Runs whose `# plant:` or channel units differ from the first run's are refused, naming
/// both, unless `allow_mixed`.
inline void check_pooled_headers(const std::vector<runlog::RunLog>& runs,
                                 const std::vector<std::string>& paths, bool allow_mixed) {
  if (allow_mixed || runs.empty()) return;
  const runlog::RunLog& first = runs.front();
  for (std::size_t r = 1; r < runs.size() && r < paths.size(); ++r) {
    const runlog::RunLog& log = runs[r];
    const auto refuse = [&](const std::string& field, const std::string& value,
                            const std::string& expected) {
      throw std::invalid_argument(paths[r] + ": " + field + " = '" + value + "', expected '" +
                                  expected + "' as in " + paths.front() +
                                  " to identify the runs together (--allow-mixed pools them "
                                  "anyway)");
    };
    if (log.plant != first.plant) refuse("plant", log.plant, first.plant);
    if (log.input_units != first.input_units)
      refuse("input units", detail::joined(log.input_units), detail::joined(first.input_units));
    if (log.output_units != first.output_units)
      refuse("output units", detail::joined(log.output_units), detail::joined(first.output_units));
  }
}

}  // namespace excite::host::cli
