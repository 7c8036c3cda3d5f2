// SPDX-License-Identifier: MIT
#pragma once
// The naive baseline: the whole discretised plant as one dense state-space model
// x⁺ = A x + B u, y = C x + D u with Eigen dynamic matrices, delays as shift-register
// states. Same coefficients as DiscretePlant, so outputs agree to rounding.

#include <Eigen/Dense>

#include "sim/lti/discrete_plant.hpp"

namespace excite::bench {

class DenseStateSpace {
 public:
  explicit DenseStateSpace(const sim::DiscretePlant& plant);
  Eigen::Index states() const { return a_.rows(); }
  /// Simulates U (N × n) from zero state, one matrix-vector product per sample.
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& u) const;

 private:
  Eigen::MatrixXd a_, b_, c_, d_;
};

}  // namespace excite::bench
