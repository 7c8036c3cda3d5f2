// SPDX-License-Identifier: MIT
#pragma once
// A historian export → a run log (issue 13 §1, host/import/README.md):
//   1. the tags' samples resampled onto t_k = t_0 + k·T, t_0 the first sample of any tag
//      (resample.hpp; T given or the median spacing of the tags' timestamps; gap limit given
//      or 1.5·max(T, median spacing)); at most max_rows rows;
//   2. the baseline (operating point) of each tag: the mean of its good values in the
//      window [from, to] minutes from the data's start (default: the first grid point);
//   3. deviations du = u − u₀, dy = y − y₀; for CVs optionally the offset (mean) or the
//      least-squares line over the good rows removed (detrend; only sound for zero-mean
//      excitation such as PRBS or multisine: a step test's response has a trend of its own);
//   4. flags: a row where any tag is bad gets kBadValue and holds that tag's last good
//      deviation (0 before the first); the first good row after a span where an MV was bad
//      also gets kDiscontinuity — the inputs the plant saw there are unknown, so identify
//      restarts its model (host/identify/run_layout.hpp).

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "firmware/runlog/format.hpp"
#include "host/import/historian_csv.hpp"
#include "host/import/resample.hpp"

namespace excite::host::historian {

enum class Detrend { none, offset, linear };

/// One tag and the channel it becomes: the run log's name and unit.
struct TagSpec {
  std::string tag;
  std::string name;
  std::string unit = "-";
};

struct ImportOptions {
  std::vector<TagSpec> mvs;      // inputs
  std::vector<TagSpec> cvs;      // outputs
  double sample_time_min = 0.0;  // 0: the median spacing of the timestamps
  Resample resample = Resample::hold;
  double max_gap_min = 0.0;  // the gap limit of resample(); 0: 1.5·max(T, median spacing)
  Detrend detrend = Detrend::none;
  bool baseline_auto = true;       // auto_baseline(); false: the window below
  double baseline_from_min = 0.0;  // baseline window, minutes from the data's start
  double baseline_to_min = 0.0;
  runlog::TimeScales time_scales;  // --tau-high, --beta: into the run log's header (0: not known)
  // The run log's row limit: a longer grid is refused before it is allocated, naming the
  // line of the timestamp farthest from the middle of the record.
  std::size_t max_rows = std::numeric_limits<std::size_t>::max();
};

struct ImportedRun {
  double sample_time_min = 0.0;
  runlog::TimeScales time_scales;  // as given in ImportOptions
  std::vector<TagSpec> inputs, outputs;
  std::vector<double> input_baseline, output_baseline;        // absolute, engineering units
  std::vector<std::vector<double>> du, u, dy;                 // per channel, per row
  std::vector<std::uint32_t> flags;                           // per row
  std::size_t bad_rows = 0;                                   // rows flagged kBadValue
  std::size_t discontinuities = 0;                            // rows flagged kDiscontinuity
  std::vector<std::size_t> bad_points;                        // per channel (inputs, then outputs)
  std::vector<double> removed_offset, removed_slope_per_min;  // per output (detrend)
  bool start_at_rest = true;  // false: the record starts mid-test (auto_baseline)
  std::string baseline_note;  // how the baselines were taken, for the run log's header
  std::size_t rows() const { return flags.size(); }
};

/// How `--baseline auto` takes the baselines (issue 18 §2): a historian record may start
/// mid-test, the MVs already away from their operating point.
///  - The first MV move: the first row where any MV leaves its first value by more than
///    1e-3 of its range over the record. The window before it is steady when it lasts at
///    least τ_H (or, τ_H unknown, min(60 rows, a tenth of the record)) and no CV drifts in
///    it (its least-squares line moves by less than a tenth of the CV's range over the
///    record). Then every baseline is the mean over that window: the start is at rest.
///  - Otherwise every baseline is the record's mean (for a test whose excitation is
///    symmetric about the operating point, the MVs' mean is their operating point), and the
///    start is not at rest: the run log says so (`# start_at_rest: no`) and identify
///    estimates each segment's initial state (`--initial-state auto`).
struct AutoBaseline {
  std::size_t steady_rows = 0;  // rows of the steady window; 0 when there is none
  bool at_rest = false;
  std::string note;  // "steady window 0 … 45 min" or "start not at rest: …"
};
AutoBaseline auto_baseline(const std::vector<std::vector<double>>& values, std::size_t mvs,
                           double T_min, double tau_high_min);

/// Throws std::invalid_argument naming the file, the tag or option, the value and what was
/// expected (a channel name that is not valid, a tag with no good value in the baseline
/// window, fewer than two grid rows, …).
ImportedRun import_historian(const HistorianData& data, const ImportOptions& options);

/// The run log text (format v2, firmware/runlog/README.md): plant `historian <source>`,
/// plan `excite import`, producer `excite import <version>`.
std::string run_log_text(const ImportedRun& run, const std::string& source);

}  // namespace excite::host::historian
