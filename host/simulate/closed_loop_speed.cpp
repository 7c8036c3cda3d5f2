// SPDX-License-Identifier: MIT
#include "host/simulate/closed_loop_speed.hpp"

#include <Eigen/Dense>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace excite::host {

ClosedLoopSpeed closed_loop_speed(const Eigen::VectorXd& step, int hold_rows,
                                  double sample_time_min, sim::Plant& plant,
                                  sim::control::Controller& controller,
                                  const ClosedLoopOptions& loop) {
  if (!(step.allFinite() && step.squaredNorm() > 0.0)) {
    char norm[32];
    std::snprintf(norm, sizeof norm, "%g", step.norm());
    throw std::invalid_argument(std::string("closed-loop speed: setpoint step of norm ") + norm +
                                ", expected a finite step that is not zero");
  }
  if (hold_rows < 2) {
    throw std::invalid_argument("closed-loop speed: hold = " + std::to_string(hold_rows) +
                                " rows, expected at least 2");
  }
  Eigen::MatrixXd r(2 * hold_rows, step.size());
  r.topRows(hold_rows).rowwise() = -step.transpose();
  r.bottomRows(hold_rows).rowwise() = step.transpose();
  ClosedLoopOptions setpoint = loop;
  setpoint.excitation = runlog::Excitation::setpoint;
  const SimulatedRun run = simulate_closed_loop(r, "closed-loop speed", sample_time_min, plant,
                                                controller, setpoint, SimulationOptions{});
  const Eigen::VectorXd swing = 2.0 * step;
  const Eigen::VectorXd before = run.dy.row(hold_rows - 1).transpose();
  for (int k = hold_rows; k < 2 * hold_rows; ++k) {
    const double share = (run.dy.row(k).transpose() - before).dot(swing) / swing.squaredNorm();
    if (share >= 0.63) return {static_cast<double>(k - hold_rows) * sample_time_min, true};
  }
  return {static_cast<double>(hold_rows) * sample_time_min, false};
}

}  // namespace excite::host
