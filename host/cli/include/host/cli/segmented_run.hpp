// SPDX-License-Identifier: MIT
#pragma once
// validate and balance on run logs with flagged rows (issue 23 §4), by identify's rule
// (host/identify/run_layout.hpp): a segment starts at the run's first row, at a row flagged
// discontinuity or skipped and after a comm_lost span; rows flagged suspended, stale,
// clamped, bad_value or comm_lost are not scored (still driven by their logged inputs);
// the warm-up after a restart inside the run is not scored; a segment with fewer than 10
// scored rows is dropped. A log without flags is one segment with every row scored, and
// gives what the commands gave before.

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "host/cli/run_input.hpp"
#include "host/identify/model.hpp"
#include "host/identify/run_layout.hpp"

namespace excite::host::cli {

struct SegmentedRun {
  runlog::RunLog log;
  StackedRuns data;  // U, Y, T and the layout of the one run
};

/// Reads a run log (read_log's checks) and lays it out by `rule` (default: identify's).
inline SegmentedRun read_segmented_run(const std::string& path, const FlagRule& rule = {}) {
  SegmentedRun run{read_log(path), {}};
  run.data = stack_runs({&run.log}, {path}, rule);
  return run;
}

/// Rows of `s` that `layout` scores.
inline Eigen::Index scored_in(const SampleLayout& layout, const Segment& s) {
  Eigen::Index n = 0;
  for (Eigen::Index k = s.begin; k < s.end; ++k) n += layout.weight(k) > 0.0 ? 1 : 0;
  return n;
}

/// Segments that hold scored rows (dropped ones hold none).
inline std::vector<Segment> scored_segments(const SampleLayout& layout) {
  std::vector<Segment> out;
  for (const Segment& s : layout.segments) {
    if (scored_in(layout, s) > 0) out.push_back(s);
  }
  return out;
}

/// The model's outputs for U, simulated from rest at the start of every segment.
inline Eigen::MatrixXd simulate_per_segment(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                                            const SampleLayout& layout) {
  Eigen::MatrixXd Y_hat = Eigen::MatrixXd::Zero(U.rows(), model.outputs);
  for (const Segment& s : layout.segments) {
    Y_hat.middleRows(s.begin, s.end - s.begin) =
        simulate(model, U.middleRows(s.begin, s.end - s.begin));
  }
  return Y_hat;
}

}  // namespace excite::host::cli
