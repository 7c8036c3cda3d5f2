// SPDX-License-Identifier: MIT
#include "host/adaptive/residual_colour.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace excite::host {

Eigen::VectorXd long_run_variance_ratio(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                                        const Eigen::MatrixXd& Y, int lags) {
  if (U.rows() != Y.rows() || Y.cols() != model.outputs) {
    throw std::invalid_argument("residual colour: U is " + std::to_string(U.rows()) + " rows, Y " +
                                std::to_string(Y.rows()) + " x " + std::to_string(Y.cols()) +
                                ", expected the same rows and " + std::to_string(model.outputs) +
                                " outputs");
  }
  if (lags < 1) {
    throw std::invalid_argument("residual colour: lags = " + std::to_string(lags) +
                                ", expected >= 1");
  }
  const Eigen::MatrixXd e = Y - simulate(model, U);
  const Eigen::Index N = e.rows();
  const Eigen::Index L = std::min<Eigen::Index>(lags, N / 4);
  Eigen::VectorXd f(model.outputs);
  for (int j = 0; j < model.outputs; ++j) {
    const Eigen::VectorXd x = e.col(j).array() - e.col(j).mean();
    const double c0 = x.squaredNorm();
    if (!std::isfinite(c0) || !(c0 > 0.0)) {
      f(j) = std::isfinite(c0) ? 1.0 : std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    double sum = 1.0;
    for (Eigen::Index k = 1; k <= L; ++k) {
      const double rho = x.head(N - k).dot(x.tail(N - k)) / c0;
      sum += 2.0 * (1.0 - static_cast<double>(k) / static_cast<double>(L + 1)) * rho;
    }
    f(j) = sum;
  }
  return f;
}

std::optional<GainUncertainty> inflated_gain_uncertainty(const IdentificationResult& result,
                                                         const Eigen::VectorXd& ratio) {
  const IdentifiedModel& m = result.model;
  if (!result.gain || !result.gain_uncertainty || !ratio.allFinite() || ratio.size() != m.outputs ||
      static_cast<int>(m.gain_covariance.size()) != m.outputs) {
    return std::nullopt;
  }
  std::vector<Eigen::MatrixXd> rows = m.gain_covariance;
  for (int j = 0; j < m.outputs; ++j) rows[static_cast<std::size_t>(j)] *= std::max(1.0, ratio(j));
  return gain_uncertainty(result.gain->gain, rows);
}

}  // namespace excite::host
