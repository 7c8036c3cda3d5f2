// SPDX-License-Identifier: MIT
#pragma once
// Steady state of a column model: f(s; op) = 0 by Newton's method, globalised by
// pseudo-transient continuation: when a full Newton step does not halve the residual, the
// step solves (I/Δt − J) δ = f instead (implicit Euler of the column's own dynamics), with
// Δt growing as the residual falls; near the solution it is plain Newton.

#include <Eigen/Dense>

#include "sim/column/column_model.hpp"

namespace excite::sim::column {

struct SteadyStateResult {
  Eigen::VectorXd state;
  double residual = 0.0;  ///< max |f_i| at the solution, state units per minute
  int iterations = 0;
};

/// Solves from `guess`. Throws std::runtime_error (naming the model, residual and
/// iterations) if it does not reach max|f| ≤ tolerance, or std::invalid_argument if the
/// operating point is invalid or drives the column out of its physical range.
SteadyStateResult solve_steady_state(const ColumnModel& model, const Operating& op,
                                     const Eigen::VectorXd& guess, double tolerance = 1e-12);

}  // namespace excite::sim::column
