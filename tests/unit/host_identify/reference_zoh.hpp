// SPDX-License-Identifier: MIT
#pragma once
// Test oracle: the (6.1.1) element simulated under a ZOH input with a fractional delay by
// integrating its state-space cascade exactly with the matrix exponential over the two
// sub-intervals of every sample (before and after the delayed input switches). Independent
// of the Van Loan / Markov-parameter discretisation in sim/lti/discretise.cpp.

#include <Eigen/Dense>
#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "host/identify/element.hpp"

namespace excite::host::testing {

inline Eigen::VectorXd reference_response(const ElementModel& g, double T,
                                          const Eigen::VectorXd& u) {
  std::vector<double> taus;
  if (g.tau1_min > 0.0) taus.push_back(g.tau1_min);
  if (g.tau2_min > 0.0) taus.push_back(g.tau2_min);
  const auto s = static_cast<Eigen::Index>(taus.size());
  const auto d = static_cast<Eigen::Index>(std::floor(g.delay_min / T));
  const double theta = g.delay_min - static_cast<double>(d) * T;
  const auto input = [&](Eigen::Index k) { return k >= 0 && k < u.size() ? u(k) : 0.0; };
  Eigen::VectorXd y(u.size());
  if (s == 0) {
    for (Eigen::Index k = 0; k < u.size(); ++k) {
      y(k) = g.gain * (theta > 0.0 ? input(k - d - 1) : input(k - d));
    }
    return y;
  }
  // Cascade x1' = (v − x1)/τ1, x2' = (x1 − x2)/τ2; y = K x_last.
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(s + 1, s + 1);
  for (Eigen::Index i = 0; i < s; ++i) {
    M(i, i) = -1.0 / taus[static_cast<std::size_t>(i)];
    if (i == 0) {
      M(i, s) = 1.0 / taus[0];
    } else {
      M(i, i - 1) = 1.0 / taus[static_cast<std::size_t>(i)];
    }
  }
  const Eigen::MatrixXd E1 = (M * theta).exp();
  const Eigen::MatrixXd E2 = (M * (T - theta)).exp();
  Eigen::VectorXd z = Eigen::VectorXd::Zero(s + 1);  // state plus the held input
  for (Eigen::Index k = 0; k < u.size(); ++k) {
    y(k) = g.gain * z(s - 1);
    z(s) = input(k - d - 1);
    z = E1 * z;
    z(s) = input(k - d);
    z = E2 * z;
  }
  return y;
}

}  // namespace excite::host::testing
