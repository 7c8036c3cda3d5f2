// SPDX-License-Identifier: MIT
#pragma once
// Run logs as the commands read them: a clear error naming file, line and column, or the
// data with its channel names. The limits (host/README.md, "Limits";
// host/identify/run_log_limits.hpp) are the reader's, checked while it reads.

#include <stdexcept>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "host/identify/run_data.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/output/input_path.hpp"

namespace excite::host::cli {

struct Run {
  runlog::RunLog log;
  RunData data;
};

/// The log as read, with the size and value checks, without run_data(): the commands that
/// apply the flags rule (identify, validate, balance) take rows flagged skipped or
/// discontinuity as segment starts, which run_data() refuses.
/// The file is opened once: the reader enforces the limits while reading
/// (host/identify/run_log_limits.hpp).
inline runlog::RunLog read_log(const std::string& path) {
  refuse_directory(path, "a run log (CSV)");
  runlog::ReadResult r = runlog::read_run_log(path, limited_read_options());
  if (!r.ok()) throw std::invalid_argument(r.error->to_string());
  return std::move(r.log);
}

inline Run read_run(const std::string& path) {
  Run run{read_log(path), {}};
  run.data = run_data(run.log);
  return run;
}

}  // namespace excite::host::cli
