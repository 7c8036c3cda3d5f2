// SPDX-License-Identifier: MIT
#include "host/identify/residuals.hpp"

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>

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

ResidualTests residual_tests(const Eigen::VectorXd& e, const Eigen::MatrixXd& U, int lags) {
  const Eigen::Index N = e.size();
  if (lags < 1 || 2 * static_cast<Eigen::Index>(lags) >= N) {
    throw std::invalid_argument("residual_tests: lags " + std::to_string(lags) + ", expected 1 … " +
                                std::to_string((N - 1) / 2) + " for " + std::to_string(N) +
                                " residuals");
  }
  const ResidualCorrelation r = residual_correlation(e, U, lags);
  ResidualTests t;
  t.lags = lags;
  const auto n_rows = static_cast<double>(N);
  for (int tau = 1; tau <= lags; ++tau) {
    const double rho = r.auto_correlation(tau);
    t.whiteness += rho * rho / (n_rows - tau);
  }
  t.whiteness *= n_rows * (n_rows + 2.0);
  const boost::math::chi_squared chi_l(lags), chi_l1(lags + 1);
  t.whiteness_limit = boost::math::quantile(chi_l, 0.99);
  t.independence_limit = boost::math::quantile(chi_l1, 0.99);
  t.independence = Eigen::VectorXd::Zero(U.cols());
  for (Eigen::Index i = 0; i < U.cols(); ++i) {
    const Eigen::VectorXd u = U.col(i).array() - U.col(i).mean();
    const double ruu0 = u.squaredNorm() / n_rows;
    if (!(ruu0 > 0.0)) continue;
    Eigen::MatrixXd R(lags + 1, lags + 1);  // Toeplitz: R(a, b) = r_uu(|a − b|)/r_uu(0)
    for (int a = 0; a <= lags; ++a) {
      const double rho = lagged_product(u, u, a) / ruu0;
      for (int b = 0; b + a <= lags; ++b) R(b, b + a) = R(b + a, b) = rho;
    }
    const Eigen::VectorXd rue = r.cross_correlation.col(i).tail(lags + 1);  // τ = 0 … L
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(R);
    t.independence(i) = n_rows * rue.dot(ldlt.solve(rue));
  }
  return t;
}

}  // namespace excite::host
