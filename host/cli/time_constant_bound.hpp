// SPDX-License-Identifier: MIT
#pragma once
// The upper bound of the identified time constants (SPEC §6: default β·τ_H), as `identify`
// and `crossval` take it: --max-time-constant MIN if given, else --beta × --tau-high, else
// β × τ_H of the case study of the run log's plant, else the run's length (identify()'s 0).

#include <CLI/CLI.hpp>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "host/cli/number_checks.hpp"
#include "host/cli/text_table.hpp"
#include "host/design/case_studies.hpp"

namespace excite::host::cli {

struct TimeConstantBoundOptions {
  double max_time_constant_min = -1.0;  // < 0: from β·τ_H
  double tau_high_min = 0.0;            // 0: the run's plant case study's τ_H
  double beta = 3.0;                    // settling time in units of τ_H
};

inline void add_time_constant_bound_options(CLI::App* cmd, TimeConstantBoundOptions& o) {
  cmd->add_option("--max-time-constant", o.max_time_constant_min,
                  "upper bound of every time constant, min (0: the run's length); default "
                  "beta x tau_H")
      ->check(finite_non_negative());
  cmd->add_option("--tau-high", o.tau_high_min,
                  "tau_H, the plant's high dominating time constant, min (default: the case "
                  "study of the run log's plant)")
      ->check(finite_positive());
  cmd->add_option("--beta", o.beta, "settling time in units of tau_H")
      ->capture_default_str()
      ->check(finite_positive());
}

/// The bound in minutes (0: identify()'s default, the run's length) and where it came from.
inline std::pair<double, std::string> time_constant_bound(const TimeConstantBoundOptions& o,
                                                          const std::string& plant) {
  if (o.max_time_constant_min >= 0.0) return {o.max_time_constant_min, "--max-time-constant"};
  if (o.tau_high_min > 0.0) return {o.beta * o.tau_high_min, "--beta x --tau-high"};
  const std::vector<std::string> known = case_study_plants();
  if (std::find(known.begin(), known.end(), plant) != known.end()) {
    const PriorKnowledge prior = case_study(plant);
    return {o.beta * prior.tau_high_min, "beta x tau_H of the " + plant + " case study, tau_H = " +
                                             num(prior.tau_high_min) + " min"};
  }
  return {0.0, "the run's length: plant \"" + plant +
                   "\" has no case study; give --tau-high or --max-time-constant"};
}

}  // namespace excite::host::cli
