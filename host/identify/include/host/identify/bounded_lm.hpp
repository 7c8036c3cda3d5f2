// SPDX-License-Identifier: MIT
#pragma once
// Levenberg–Marquardt with box bounds for min ‖r(x)‖², r = y − f(x).
//
// Marquardt scaling (damping λ·diag(JᵀJ)), Nielsen's update of λ, and an active set per
// iteration: a parameter on a bound whose gradient points out of the box is held for that
// iteration; the step of the others is projected back onto the box.

#include <Eigen/Dense>
#include <functional>

namespace excite::host {

struct LmProblem {
  /// r(x) = y − f(x); returns false when f cannot be evaluated at x (the step is rejected).
  std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& r)> residual;
  /// J = ∂f/∂x at x (note: of f, so r − Jδ is the linearised residual after a step δ).
  std::function<void(const Eigen::VectorXd& x, Eigen::MatrixXd& J)> jacobian;
  Eigen::VectorXd lower;  // bounds; ±inf where free
  Eigen::VectorXd upper;
  Eigen::VectorXd scale;  // typical size of each parameter, for the step-size test (> 0)
};

struct LmOptions {
  int max_iterations = 200;
  double step_tolerance = 1e-10;  // stop when every |δ_m| ≤ tol · (|x_m| + scale_m)
  // … or twice in a row the cost fell by less than cost_tolerance · σ̂², σ̂² = cost/(M − P)
  // (M residuals, P parameters): a statistically meaningless change, i.e. the parameters
  // are within about √cost_tolerance standard errors of the optimum.
  double cost_tolerance = 1e-4;
};

struct LmResult {
  Eigen::VectorXd x;
  double cost = 0.0;  // ‖r(x)‖²
  int iterations = 0;
  bool converged = false;  // false only when the iteration limit was reached
};

/// Minimises from x0 (clamped onto the box first). Precondition: residual(x0) succeeds.
LmResult minimise_bounded(const LmProblem& problem, Eigen::VectorXd x0, const LmOptions& options);

}  // namespace excite::host
