// SPDX-License-Identifier: MIT
#pragma once
// Run logs as the commands read them: a clear error naming file, line and column, or the
// data with its channel names.

#include <stdexcept>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "host/identify/run_data.hpp"

namespace excite::host::cli {

struct Run {
  runlog::RunLog log;
  RunData data;
};

inline Run read_run(const std::string& path) {
  runlog::ReadResult r = runlog::read_run_log(path);
  if (!r.ok()) throw std::invalid_argument(r.error->to_string());
  Run run{std::move(r.log), {}};
  run.data = run_data(run.log);
  return run;
}

}  // namespace excite::host::cli
