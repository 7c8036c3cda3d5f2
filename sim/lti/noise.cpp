// SPDX-License-Identifier: MIT
#include "sim/lti/noise.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace excite::sim {

double GaussianSource::next() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // u1 in (0, 1] (so the logarithm is finite), u2 in [0, 1), 53 bits each.
  constexpr double kScale = 1.0 / 9007199254740992.0;  // 2^-53
  const double u1 = (static_cast<double>(engine_() >> 11U) + 1.0) * kScale;
  const double u2 = static_cast<double>(engine_() >> 11U) * kScale;
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  spare_ = r * std::sin(angle);
  has_spare_ = true;
  return r * std::cos(angle);
}

MeasurementNoise::MeasurementNoise(std::vector<double> variances, std::uint64_t seed)
    : source_(seed) {
  if (variances.empty()) throw std::invalid_argument("noise variances, expected one per output");
  for (std::size_t i = 0; i < variances.size(); ++i) {
    const double v = variances[i];
    if (!std::isfinite(v) || v < 0.0) {
      throw std::invalid_argument("noise variance of output " + std::to_string(i + 1) + " is " +
                                  std::to_string(v) + ", expected a finite value ≥ 0");
    }
    std_dev_.push_back(std::sqrt(v));
  }
}

MeasurementNoise::MeasurementNoise(int outputs, double variance, std::uint64_t seed)
    : MeasurementNoise(
          std::vector<double>(static_cast<std::size_t>(std::max(outputs, 0)), variance), seed) {}

void MeasurementNoise::add(double* y) {
  for (std::size_t i = 0; i < std_dev_.size(); ++i) y[i] += std_dev_[i] * source_.next();
}

void MeasurementNoise::add(Eigen::MatrixXd& y) {
  if (y.cols() != outputs()) {
    throw std::invalid_argument("output matrix has " + std::to_string(y.cols()) +
                                " columns, expected " + std::to_string(outputs()));
  }
  for (Eigen::Index k = 0; k < y.rows(); ++k) {
    for (Eigen::Index i = 0; i < y.cols(); ++i) {
      y(k, i) += std_dev_[static_cast<std::size_t>(i)] * source_.next();
    }
  }
}

}  // namespace excite::sim
