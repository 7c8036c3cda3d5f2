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

/// H = JᵀJ, both triangles, a column at a time: H(0..a, a) = J(:, 0..a)ᵀ J(:, a) by Eigen's
/// matrix–vector kernel (several dot products per pass over J(:, a)). For the tall, narrow
/// Jacobians of the row fits (N ≈ 4 000, P = 3–23) it takes 1/1.4 to 1/4.2 of the time of
/// Eigen's symmetric rank update, whose packing dominates at small P (tests/bench/host_identify,
/// normal_matrix_bench). Its sums are ordered otherwise: they agree to rounding (~1e-15).
void normal_matrix(const Eigen::MatrixXd& J, Eigen::MatrixXd& H);

/// Minimises from x0 (clamped onto the box first). Precondition: residual(x0) succeeds.
LmResult minimise_bounded(const LmProblem& problem, Eigen::VectorXd x0, const LmOptions& options);

}  // namespace excite::host
