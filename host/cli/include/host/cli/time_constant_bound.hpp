// SPDX-License-Identifier: MIT
#pragma once
// The upper bound of the identified time constants (SPEC §6: β·τ_H), as `identify` and
// `crossval` take it, first found of:
//   --max-time-constant MIN (0: the run's length, accepted on purpose);
//   --tau-high × (--beta, else the run log's β, else 3);
//   the run logs' own `# tau_high_min:` × `# beta:` header (the plan's design, carried by
//   every producer: firmware/runlog/README.md) — the largest when runs differ;
//   the case study of the run log's plant name (logs written before the header existed);
// otherwise no bound is known and the command refuses, naming the options: a bound of the
// run's length lets an element absorb another's misfit with a slow lag and a large gain
// (σ₄ of alatiqi4x4 came out 3.9× too large so).

#include <CLI/CLI.hpp>
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "firmware/runlog/format.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/text_table.hpp"
#include "host/design/case_studies.hpp"

namespace excite::host::cli {

struct TimeConstantBoundOptions {
  double max_time_constant_min = -1.0;  // < 0: not given
  double tau_high_min = 0.0;            // 0: not given
  double beta = 0.0;                    // 0: not given (the run log's β, else 3)
};

inline void add_time_constant_bound_options(CLI::App* cmd, TimeConstantBoundOptions& o) {
  cmd->add_option("--max-time-constant", o.max_time_constant_min,
                  "upper bound of every time constant, min (0: the run's length); default "
                  "beta x tau_H of the run log's design")
      ->check(finite_non_negative());
  cmd->add_option("--tau-high", o.tau_high_min,
                  "tau_H, the plant's high dominating time constant, min (default: the run "
                  "log's tau_high_min, written from the plan)")
      ->check(finite_positive());
  cmd->add_option("--beta", o.beta,
                  "settling time in units of tau_H (default: the run log's beta, else 3)")
      ->check(finite_positive());
}

/// What a run says of its design: its plant's name and its header's time scales.
struct RunTimeScales {
  std::string path;
  std::string plant;
  runlog::TimeScales scales;
};

/// The bound in minutes (0: identify()'s run length, only when asked for with
/// --max-time-constant 0) and where it came from. Throws std::invalid_argument naming the
/// options when no bound is known.
inline std::pair<double, std::string> time_constant_bound(const TimeConstantBoundOptions& o,
                                                          const std::vector<RunTimeScales>& runs) {
  if (o.max_time_constant_min > 0.0) return {o.max_time_constant_min, "--max-time-constant"};
  if (o.max_time_constant_min == 0.0) return {0.0, "the run's length, --max-time-constant 0"};
  const auto beta_of = [&](const runlog::TimeScales& s) {
    return o.beta > 0.0 ? o.beta : s.beta > 0.0 ? s.beta : 3.0;
  };
  if (o.tau_high_min > 0.0) {
    const runlog::TimeScales none;
    const double beta = beta_of(runs.empty() ? none : runs.front().scales);
    return {beta * o.tau_high_min, "beta " + num(beta) + " x --tau-high"};
  }
  const RunTimeScales* widest = nullptr;
  for (const RunTimeScales& r : runs) {
    if (r.scales.tau_high_min <= 0.0) continue;
    if (widest == nullptr || beta_of(r.scales) * r.scales.tau_high_min >
                                 beta_of(widest->scales) * widest->scales.tau_high_min) {
      widest = &r;
    }
  }
  if (widest != nullptr) {
    const double beta = beta_of(widest->scales);
    return {beta * widest->scales.tau_high_min,
            "beta x tau_H of the run log " + widest->path + ", beta = " + num(beta) +
                ", tau_H = " + num(widest->scales.tau_high_min) + " min"};
  }
  const std::vector<std::string> known = case_study_plants();
  for (const RunTimeScales& r : runs) {
    if (std::find(known.begin(), known.end(), r.plant) == known.end()) continue;
    const PriorKnowledge prior = case_study(r.plant);
    const double beta = o.beta > 0.0 ? o.beta : prior.beta;
    return {beta * prior.tau_high_min, "beta x tau_H of the " + r.plant + " case study, tau_H = " +
                                           num(prior.tau_high_min) + " min"};
  }
  const std::string path = runs.empty() ? std::string("the run") : runs.front().path;
  throw std::invalid_argument(
      path + ": tau_high_min = (not in the run log's header, and plant \"" +
      (runs.empty() ? std::string() : runs.front().plant) +
      "\" has no case study), expected the design's time scale: give --tau-high MIN (the bound "
      "is beta x tau_H), --max-time-constant MIN, or --max-time-constant 0 to accept the run's "
      "length (an element may then absorb another's misfit with a slow lag and a large gain)");
}

}  // namespace excite::host::cli
