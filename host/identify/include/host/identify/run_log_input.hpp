// SPDX-License-Identifier: MIT
#pragma once
// Run logs as the host's commands read them: each file opened once, the limits
// (run_log_limits.hpp) enforced by the reader while it reads, a clear error naming file, line
// and column; several logs pooled for one identification; one log laid out in segments by
// identify's flags rule (issue 23 §4, run_layout.hpp): a segment starts at the run's first
// row, at a row flagged discontinuity or skipped and after a comm_lost span; rows flagged
// suspended, stale, clamped, bad_value or comm_lost are not scored (still driven by their
// logged inputs); the warm-up after a restart inside the run is not scored; a segment with
// fewer than 10 scored rows is dropped. A log without flags is one segment with every row
// scored.

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "host/identify/model.hpp"
#include "host/identify/run_layout.hpp"

namespace excite::host {

/// The log as read, with the size and value checks, without run_data(): the commands that
/// apply the flags rule (identify, validate, balance) take rows flagged skipped or
/// discontinuity as segment starts, which run_data() refuses. A directory is refused.
runlog::RunLog read_log(const std::string& path);

/// Reads every run (excite identify RUN…), each file opened once: at most kMaxRunRows data
/// rows over all `paths` together, enforced by the reader as it reads (each run may hold what
/// the earlier ones left); the run that crosses the limit is named with the count of runs.
std::vector<runlog::RunLog> read_pooled_logs(const std::vector<std::string>& paths);

/// Runs are pooled only when their headers say they come from the same plant with the same
/// units: a run whose `# plant:` or channel units differ from the first run's is refused,
/// naming both, unless `allow_mixed`.
void check_pooled_headers(const std::vector<runlog::RunLog>& runs,
                          const std::vector<std::string>& paths, bool allow_mixed);

struct SegmentedRun {
  runlog::RunLog log;
  StackedRuns data;  // U, Y, T and the layout of the one run
};

/// Reads a run log (read_log's checks) and lays it out by `rule` (default: identify's).
SegmentedRun read_segmented_run(const std::string& path, const FlagRule& rule = {});

/// Rows of `s` that `layout` scores.
Eigen::Index scored_in(const SampleLayout& layout, const Segment& s);

/// Segments that hold scored rows (dropped ones hold none).
std::vector<Segment> scored_segments(const SampleLayout& layout);

/// The model's outputs for U, simulated from rest at the start of every segment.
Eigen::MatrixXd simulate_per_segment(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                                     const SampleLayout& layout);

}  // namespace excite::host
