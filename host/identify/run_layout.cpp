// SPDX-License-Identifier: MIT
#include "host/identify/run_layout.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "firmware/runlog/format.hpp"

namespace excite::host {
namespace {

using runlog::Flag;

// Rows whose outputs are not scored (their inputs still drive the simulation).
constexpr std::uint32_t kNotScored =
    runlog::kSuspended | runlog::kCommLost | runlog::kStale | runlog::kClamped | runlog::kBadValue;
// A row that starts a new segment: the plant's state is not the model's continuation.
constexpr std::uint32_t kRestart = runlog::kDiscontinuity | runlog::kSkipped;

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " ") + x;
  return s;
}

void check_same_channels(const runlog::RunLog& first, const runlog::RunLog& log,
                         const std::string& first_name, const std::string& name) {
  if (log.input_names != first.input_names || log.output_names != first.output_names) {
    throw std::invalid_argument(name + ": inputs '" + join(log.input_names) + "', outputs '" +
                                join(log.output_names) + "', expected those of " + first_name +
                                " (inputs '" + join(first.input_names) + "', outputs '" +
                                join(first.output_names) + "') to identify the runs together");
  }
  if (std::abs(log.sample_time_min - first.sample_time_min) > 1e-9 * first.sample_time_min) {
    throw std::invalid_argument(
        name + ": sample_time_min = " + std::to_string(log.sample_time_min) + ", expected " +
        std::to_string(first.sample_time_min) + " as in " + first_name);
  }
}

Eigen::Index rows_of(double minutes, double T) {
  return minutes <= 0.0 ? 0 : static_cast<Eigen::Index>(std::ceil(minutes / T - 1e-9));
}

}  // namespace

const char* flag_name(int bit) {
  static const char* const names[] = {"suspended", "comm_lost", "clamped",       "rate_limited",
                                      "stale",     "skipped",   "discontinuity", "bad_value"};
  return bit >= 0 && bit < 8 ? names[bit] : "unknown";
}

StackedRuns stack_runs(const std::vector<const runlog::RunLog*>& logs,
                       const std::vector<std::string>& names, const FlagRule& rule) {
  if (logs.empty() || names.size() != logs.size()) {
    throw std::invalid_argument("identify: " + std::to_string(logs.size()) + " runs and " +
                                std::to_string(names.size()) +
                                " names, expected at least one run, one name each");
  }
  if (!(rule.warm_up_min >= 0.0) || !(rule.start_warm_up_min >= 0.0) || rule.min_segment_rows < 1) {
    throw std::invalid_argument("identify: warm-up " + std::to_string(rule.warm_up_min) +
                                " min, start warm-up " + std::to_string(rule.start_warm_up_min) +
                                " min, min segment rows " + std::to_string(rule.min_segment_rows) +
                                ", expected warm-ups ≥ 0 and ≥ 1 row");
  }
  const runlog::RunLog& first = *logs.front();
  Eigen::Index N = 0;
  for (std::size_t r = 0; r < logs.size(); ++r) {
    check_same_channels(first, *logs[r], names.front(), names[r]);
    N += static_cast<Eigen::Index>(logs[r]->rows());
  }
  const auto n = static_cast<Eigen::Index>(first.input_names.size());
  const auto p = static_cast<Eigen::Index>(first.output_names.size());
  const double T = first.sample_time_min;

  StackedRuns out;
  out.sample_time_min = T;
  out.U.resize(N, n);
  out.Y.resize(N, p);
  out.layout.weight = Eigen::VectorXd::Ones(N);
  LayoutReport& rep = out.report;
  rep.rows = N;

  // Segment starts and the warm-up each needs.
  struct Start {
    Eigen::Index row;
    Eigen::Index warm_up;
  };
  std::vector<Start> starts;
  Eigen::Index base = 0;
  for (const runlog::RunLog* log : logs) {
    const auto rows = static_cast<Eigen::Index>(log->rows());
    for (Eigen::Index i = 0; i < n; ++i) {
      out.U.col(i).segment(base, rows) =
          Eigen::Map<const Eigen::VectorXd>(log->du[static_cast<std::size_t>(i)].data(), rows);
    }
    for (Eigen::Index j = 0; j < p; ++j) {
      out.Y.col(j).segment(base, rows) =
          Eigen::Map<const Eigen::VectorXd>(log->dy[static_cast<std::size_t>(j)].data(), rows);
    }
    // A closed-loop run's clamped rows are the controller's MVs on their box limits: the
    // logged u is what the plant got, and the controller saturates when the disturbance is
    // large, so leaving them out would choose rows by the disturbance (run_layout.hpp).
    const std::uint32_t not_scored =
        log->closed_loop.closed ? kNotScored & ~static_cast<std::uint32_t>(runlog::kClamped)
                                : kNotScored;
    bool comm_lost_before = false;
    for (Eigen::Index k = 0; k < rows; ++k) {
      const std::uint32_t f = log->flags[static_cast<std::size_t>(k)];
      for (int b = 0; b < 8; ++b) {
        if ((f & (1U << b)) != 0U) ++rep.rows_with_flag[static_cast<std::size_t>(b)];
      }
      if ((f & runlog::kDiscontinuity) != 0U) ++rep.discontinuities;
      if ((f & runlog::kSkipped) != 0U) ++rep.skips;
      const bool comm_lost = (f & runlog::kCommLost) != 0U;
      if (k == 0) {
        starts.push_back({base, rows_of(rule.start_warm_up_min, T)});
      } else if ((f & kRestart) != 0U || (!rule.keep_flagged && comm_lost_before && !comm_lost)) {
        starts.push_back({base + k, rows_of(rule.warm_up_min, T)});
      }
      comm_lost_before = comm_lost;
      if (!rule.keep_flagged && (f & not_scored) != 0U) {
        out.layout.weight(base + k) = 0.0;
        ++rep.flagged_excluded;
      }
    }
    base += rows;
  }

  for (std::size_t s = 0; s < starts.size(); ++s) {
    const Eigen::Index b = starts[s].row;
    const Eigen::Index e = s + 1 < starts.size() ? starts[s + 1].row : N;
    out.layout.segments.push_back(Segment{b, e});
    for (Eigen::Index k = b; k < std::min(e, b + starts[s].warm_up); ++k) {
      if (out.layout.weight(k) != 0.0) {
        out.layout.weight(k) = 0.0;
        ++rep.warm_up;
      }
    }
    const auto scored = static_cast<Eigen::Index>(out.layout.weight.segment(b, e - b).sum());
    if (scored < rule.min_segment_rows) {
      out.layout.weight.segment(b, e - b).setZero();
      rep.dropped_segment_rows += scored;
      ++rep.dropped_segments;
    } else {
      ++rep.segments;
    }
  }
  rep.scored = out.layout.scored();
  return out;
}

std::string layout_summary(const LayoutReport& r, std::size_t runs) {
  std::ostringstream s;
  s << r.scored << " of " << r.rows << " rows scored in " << r.segments << " segment"
    << (r.segments == 1 ? "" : "s") << " (" << runs << " run" << (runs == 1 ? "" : "s") << ")";
  if (r.flagged_excluded > 0) {
    s << "; " << r.flagged_excluded << " flagged rows excluded (";
    bool first = true;
    for (int b = 0; b < 8; ++b) {
      const Eigen::Index c = r.rows_with_flag[static_cast<std::size_t>(b)];
      if (c == 0) continue;
      s << (first ? "" : ", ") << flag_name(b) << ' ' << c;
      first = false;
    }
    s << ')';
  }
  if (r.discontinuities > 0) s << "; " << r.discontinuities << " discontinuities (plant restart)";
  if (r.skips > 0) s << "; " << r.skips << " skipped-tick rows";
  if (r.warm_up > 0) s << "; " << r.warm_up << " warm-up rows not scored";
  if (r.dropped_segments > 0) {
    s << "; " << r.dropped_segments << " short segments dropped (" << r.dropped_segment_rows
      << " rows)";
  }
  return s.str();
}

bool needs_warning(const LayoutReport& r) {
  Eigen::Index flagged = 0;
  for (const Eigen::Index c : r.rows_with_flag) flagged += c;
  return flagged > 0 || r.dropped_segments > 0 || r.warm_up > 0;
}

}  // namespace excite::host
