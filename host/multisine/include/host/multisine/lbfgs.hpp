// SPDX-License-Identifier: MIT
#pragma once
// A small limited-memory BFGS minimiser (Nocedal & Wright, Algorithm 7.4, two-loop
// recursion) with a backtracking Armijo line search. Used by the crest-factor optimiser;
// unconstrained, smooth objectives only.

#include <Eigen/Dense>
#include <functional>

namespace excite::host::multisine {

/// f(x, gradient) returns the value at x and writes ∂f/∂x into `gradient` (same size as x).
using Objective = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& gradient)>;

struct LbfgsOptions {
  int memory = 8;                    // correction pairs kept
  int max_iterations = 40;           // outer iterations
  double max_first_step = 0.2;       // largest |Δx_i| of the first (steepest-descent) step
  double gradient_tolerance = 1e-9;  // stop when ‖∇f‖_∞ falls below
  double relative_decrease = 1e-9;   // stop when f decreases by less than this · |f|
};

struct LbfgsResult {
  double value = 0.0;
  int iterations = 0;
  int evaluations = 0;
};

/// Minimises f from x (updated in place to the last accepted point).
LbfgsResult lbfgs_minimise(const Objective& f, Eigen::VectorXd& x, const LbfgsOptions& options);

}  // namespace excite::host::multisine
