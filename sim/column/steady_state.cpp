// SPDX-License-Identifier: MIT
#include "sim/column/steady_state.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace excite::sim::column {

SteadyStateResult solve_steady_state(const ColumnModel& model, const Operating& op,
                                     const Eigen::VectorXd& guess, double tolerance) {
  validate(op, model.name() + " steady state");
  const Eigen::Index n = model.state_size();
  Eigen::VectorXd s = guess;
  Eigen::VectorXd f(n);
  model.derivative(s, op, f);
  double residual = f.lpNorm<Eigen::Infinity>();
  double dt_min = 0.1;  // pseudo time step of the fallback; grows as the residual falls
  constexpr int kMaxIterations = 400;
  int it = 0;
  Eigen::VectorXd trial(n), f_trial(n);
  auto attempt = [&](const Eigen::MatrixXd& m) {
    trial = s + m.partialPivLu().solve(f);
    model.derivative(trial, op, f_trial);
    return f_trial.lpNorm<Eigen::Infinity>();
  };
  for (; it < kMaxIterations && !(residual <= tolerance); ++it) {
    const Eigen::MatrixXd minus_j = -model.jacobian(s, op);
    // Plain Newton first: taken when it halves the residual.
    double r_trial = attempt(minus_j);
    if (!(std::isfinite(r_trial) && r_trial < 0.5 * residual)) {
      // Pseudo-transient step: implicit Euler of the column's own dynamics with step Δt.
      Eigen::MatrixXd m = minus_j;
      m.diagonal().array() += 1.0 / dt_min;
      r_trial = attempt(m);
      if (!std::isfinite(r_trial) || r_trial > 10.0 * residual) {
        dt_min *= 0.2;  // overshoot: back off towards the transient
        continue;
      }
      // Switched evolution relaxation, growing at least 1.5× per accepted step.
      dt_min = std::min(dt_min * std::max(1.5, std::min(residual / r_trial, 10.0)), 1e15);
    }
    s.swap(trial);
    f.swap(f_trial);
    residual = r_trial;
  }
  if (!(residual <= tolerance)) {
    std::ostringstream msg;
    msg << model.name() << ": steady state not found at L = " << op.reflux_kmol_min
        << ", V = " << op.boilup_kmol_min << ", F = " << op.feed_kmol_min
        << ", z_F = " << op.feed_light << " (residual " << residual << " after " << it
        << " iterations)";
    throw std::runtime_error(msg.str());
  }
  model.check_state(s);
  return SteadyStateResult{s, residual, it};
}

}  // namespace excite::sim::column
