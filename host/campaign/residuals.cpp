// SPDX-License-Identifier: MIT
#include "host/campaign/residuals.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace excite::host {
namespace {

// (1/N) Σ_k a(k) b(k + lag), over the k where both exist.
double lagged_product(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int lag) {
  const Eigen::Index N = a.size();
  const Eigen::Index shift = std::abs(lag);
  const Eigen::Index count = N - shift;
  if (count <= 0) return 0.0;
  return lag >= 0 ? a.head(count).dot(b.tail(count)) / static_cast<double>(N)
                  : a.tail(count).dot(b.head(count)) / static_cast<double>(N);
}

}  // namespace

ResidualCorrelation residual_correlation(const Eigen::VectorXd& e, const Eigen::MatrixXd& U,
                                         int max_lag) {
  const Eigen::Index N = e.size();
  if (U.rows() != N) {
    throw std::invalid_argument("residual_correlation: " + std::to_string(U.rows()) +
                                " input rows for " + std::to_string(N) +
                                " residuals, expected the same");
  }
  if (max_lag < 1 || max_lag >= N) {
    throw std::invalid_argument("residual_correlation: max_lag " + std::to_string(max_lag) +
                                ", expected 1 … " + std::to_string(N - 1));
  }
  ResidualCorrelation r;
  r.max_lag = max_lag;
  r.limit_99 = 2.58 / std::sqrt(static_cast<double>(N));
  const Eigen::VectorXd ec = e.array() - e.mean();
  const double ree0 = ec.squaredNorm() / static_cast<double>(N);
  r.auto_correlation = Eigen::VectorXd::Zero(max_lag + 1);
  r.cross_correlation = Eigen::MatrixXd::Zero(2 * max_lag + 1, U.cols());
  if (!(ree0 > 0.0)) return r;
  for (int tau = 0; tau <= max_lag; ++tau)
    r.auto_correlation(tau) = lagged_product(ec, ec, tau) / ree0;
  for (Eigen::Index i = 0; i < U.cols(); ++i) {
    const Eigen::VectorXd u = U.col(i).array() - U.col(i).mean();
    const double ruu0 = u.squaredNorm() / static_cast<double>(N);
    if (!(ruu0 > 0.0)) continue;
    const double scale = std::sqrt(ree0 * ruu0);
    for (int tau = -max_lag; tau <= max_lag; ++tau)
      r.cross_correlation(tau + max_lag, i) = lagged_product(u, ec, tau) / scale;
  }
  return r;
}

}  // namespace excite::host
