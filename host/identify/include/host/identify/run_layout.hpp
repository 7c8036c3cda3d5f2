// SPDX-License-Identifier: MIT
#pragma once
// Run logs → identification data that honour the logs' flags (issue 10 §6, issue 13 §1).
//
// The rule (host/identify/README.md, "Flags, segments and warm-up"), per row and its flags
// (firmware/runlog/format.hpp):
//   - not scored (weight 0, still simulated with its logged inputs, so the model's state
//     carries across the span): suspended (inputs held at the baseline, logged), stale,
//     clamped (du is the clamped value written, but the design's input was not applied),
//     bad_value (a value missing or bad at its source), comm_lost; in a closed-loop run
//     (run-log v4) clamped rows are scored: there the flag says the controller's MV sat on
//     its box limit, du is what the plant got, and the controller saturates when the
//     disturbance is large, so leaving them out would choose rows by the disturbance and
//     bias the fit (issue 41 §3: the direct fit's coverage on woodberry2x2 under PI with a
//     coloured disturbance, 100 seeds, 88.5 % without them, 94.2 % with them);
//   - a NEW SEGMENT starts (the model restarts from rest, state unknown): at each run's
//     first row; at a row flagged discontinuity (the plant restarted, its time or heartbeat
//     jumped) or skipped (ticks missing before it); at the first row after a comm_lost span
//     (the writes may not have reached the plant, so the logged inputs are not known to be
//     the plant's);
//   - WARM-UP: the first ⌈warm_up_min / T⌉ rows of a segment that starts inside a run are
//     not scored (the unknown state's response dies out; default: the delay bound), the
//     first ⌈start_warm_up_min / T⌉ rows of each run likewise (default 0: a run log starts
//     at the operating point, the plant at rest — give it for data that do not);
//   - rate_limited rows are kept (du is the value written after the rate limit);
//   - a segment with fewer than min_segment_rows scored rows is dropped (not scored) and
//     counted.
// keep_flagged scores flagged rows as if good (the old behaviour; segments still start at
// discontinuities, skips and runs' starts).

#include <cstdint>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

struct FlagRule {
  bool keep_flagged = false;
  double warm_up_min = 20.0;       // after a restart inside a run
  double start_warm_up_min = 0.0;  // at each run's start
  Eigen::Index min_segment_rows = 10;
};

/// What the rule did, for the warning and the JSON.
struct LayoutReport {
  Eigen::Index rows = 0;                  // all rows of all runs
  Eigen::Index scored = 0;                // rows in the cost
  Eigen::Index flagged_excluded = 0;      // rows not scored because of their flags
  Eigen::Index warm_up = 0;               // rows not scored as warm-up
  Eigen::Index dropped_segment_rows = 0;  // rows of dropped short segments
  int segments = 0;                       // segments used (dropped ones not counted)
  int dropped_segments = 0;
  int discontinuities = 0;  // rows flagged discontinuity
  int skips = 0;            // rows flagged skipped
  // Rows carrying each flag bit, by bit (format.hpp: 0 suspended … 7 bad_value).
  std::vector<Eigen::Index> rows_with_flag = std::vector<Eigen::Index>(8, 0);
};

/// Name of flag bit b ("suspended", "comm_lost", …).
const char* flag_name(int bit);

/// One line: what the flags rule did to `runs` runs, as the commands that apply it warn.
std::string layout_summary(const LayoutReport& r, std::size_t runs);

/// Whether the rule excluded anything worth a warning: flagged rows, dropped segments or
/// warm-up rows.
bool needs_warning(const LayoutReport& r);

/// Several runs (same channels in the same order, same sample time) stacked as one data set:
/// deviations du → U, dy → Y, the layout by the rule above. `names` label errors (one per
/// log). Throws std::invalid_argument naming the run, the field and what was expected.
struct StackedRuns {
  Eigen::MatrixXd U;
  Eigen::MatrixXd Y;
  double sample_time_min = 0.0;
  SampleLayout layout;
  LayoutReport report;
};
StackedRuns stack_runs(const std::vector<const runlog::RunLog*>& logs,
                       const std::vector<std::string>& names, const FlagRule& rule);

}  // namespace excite::host
