// SPDX-License-Identifier: MIT
#pragma once
// The options of the time-constant bound (host/design/time_constant_bound.hpp), as `identify`
// and `crossval` take them.

#include <CLI/CLI.hpp>

#include "host/cli/number_checks.hpp"
#include "host/design/time_constant_bound.hpp"

namespace excite::host::cli {

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

}  // namespace excite::host::cli
