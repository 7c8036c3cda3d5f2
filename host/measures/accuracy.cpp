// SPDX-License-Identifier: MIT
#include "host/measures/accuracy.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace excite::host {

std::vector<double> principal_minor_values(const Eigen::MatrixXd& gain) {
  const auto n = static_cast<int>(gain.rows());
  std::vector<double> minors;
  for (unsigned mask = 1; mask < (1U << n); ++mask) {
    std::vector<Eigen::Index> index;
    for (int i = 0; i < n; ++i) {
      if ((mask & (1U << i)) != 0U) index.push_back(i);
    }
    minors.push_back(gain(index, index).determinant());
  }
  return minors;
}

TruePlant true_plant_of(const Eigen::MatrixXd& gain) {
  if (gain.rows() != gain.cols() || gain.rows() < 1 || gain.rows() > 16) {
    throw std::invalid_argument("accuracy criterion: G(0) is " + std::to_string(gain.rows()) +
                                " x " + std::to_string(gain.cols()) +
                                ", expected a square matrix of 1 to 16 rows");
  }
  return {analyse_gain(gain), principal_minor_values(gain)};
}

Accuracy judge(const TruePlant& truth, const std::optional<GainAnalysis>& identified) {
  Accuracy a;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  a.sigma_n_error = nan;
  a.weakest_angle_deg = nan;
  if (!identified || identified->gain.rows() != truth.gain.gain.rows() ||
      identified->gain.cols() != truth.gain.gain.cols() || !identified->gain.allFinite()) {
    return a;
  }
  a.gain_identified = true;
  const Eigen::Index n = truth.gain.singular_values.size() - 1;
  const double sigma = truth.gain.singular_values(n);
  a.sigma_n_error = (identified->singular_values(n) - sigma) / sigma;
  const Eigen::VectorXd v = truth.gain.input_directions.col(n);
  const Eigen::VectorXd v_hat = identified->input_directions.col(n);
  const double cosine = std::min(1.0, std::abs(v.dot(v_hat)) / (v.norm() * v_hat.norm()));
  a.weakest_angle_deg = std::acos(cosine) * 180.0 / std::numbers::pi;
  const std::vector<double> minors = principal_minor_values(identified->gain);
  a.minor_signs_right = true;
  for (std::size_t i = 0; i < minors.size(); ++i) {
    if (!(std::signbit(minors[i]) == std::signbit(truth.minors[i]) && minors[i] != 0.0))
      a.minor_signs_right = false;
  }
  a.met = a.minor_signs_right && std::abs(a.sigma_n_error) <= kSigmaTolerance &&
          a.weakest_angle_deg <= kAngleToleranceDeg;
  return a;
}

}  // namespace excite::host
