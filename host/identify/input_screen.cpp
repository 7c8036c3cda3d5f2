// SPDX-License-Identifier: MIT
#include "host/identify/input_screen.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace excite::host {

InputScreen screen_inputs(const Eigen::MatrixXd& U) {
  const auto n = static_cast<int>(U.cols());
  InputScreen s;
  s.status.assign(static_cast<std::size_t>(n), ElementStatus::identified);
  s.reason.assign(static_cast<std::size_t>(n), "");
  const double overall = U.size() > 0 ? U.cwiseAbs().maxCoeff() : 0.0;
  std::vector<int> moving;
  for (int i = 0; i < n; ++i) {
    if (overall == 0.0 || U.col(i).cwiseAbs().maxCoeff() <= 1e-12 * overall) {
      s.status[static_cast<std::size_t>(i)] = ElementStatus::input_not_moved;
      s.reason[static_cast<std::size_t>(i)] =
          "input " + std::to_string(i + 1) + " is zero throughout the data (never moved)";
    } else {
      moving.push_back(i);
    }
  }
  for (const int i : moving) {
    if (moving.size() < 2) break;
    Eigen::MatrixXd others(U.rows(), static_cast<Eigen::Index>(moving.size() - 1));
    Eigen::Index c = 0;
    for (const int o : moving) {
      if (o != i) others.col(c++) = U.col(o);
    }
    const Eigen::VectorXd ui = U.col(i);
    const Eigen::VectorXd coef = others.colPivHouseholderQr().solve(ui);
    const double rel = (ui - others * coef).norm() / ui.norm();
    if (rel < 1e-8) {
      s.status[static_cast<std::size_t>(i)] = ElementStatus::input_collinear;
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "input %d is a linear combination of the other inputs (relative residual "
                    "%.1e): its elements cannot be separated from theirs",
                    i + 1, rel);
      s.reason[static_cast<std::size_t>(i)] = buf;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (s.status[static_cast<std::size_t>(i)] == ElementStatus::identified) s.usable.push_back(i);
  }
  return s;
}

InputSeparation input_separation(const Eigen::MatrixXd& X) {
  const Eigen::Index m = X.cols();
  InputSeparation s;
  s.independent = Eigen::VectorXd::Ones(m);
  s.regression = Eigen::MatrixXd::Zero(m, m);
  if (m < 2) return s;
  const Eigen::VectorXd norms = X.colwise().norm().transpose();
  const Eigen::MatrixXd Xs = X * norms.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd C = Xs.transpose() * Xs;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(C);
  const double smallest = std::max(eig.eigenvalues().minCoeff(), 0.0);
  s.condition = smallest > 0.0 ? eig.eigenvalues().maxCoeff() / smallest
                               : std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < m; ++i) {
    Eigen::MatrixXd others(X.rows(), m - 1);
    for (Eigen::Index k = 0, c = 0; k < m; ++k) {
      if (k != i) others.col(c++) = Xs.col(k);
    }
    const Eigen::VectorXd b = others.colPivHouseholderQr().solve(Xs.col(i));
    s.independent(i) = (Xs.col(i) - others * b).norm();  // x_i has unit norm
    for (Eigen::Index k = 0, c = 0; k < m; ++k) {
      if (k != i) s.regression(k, i) = b(c++) * norms(i) / norms(k);
    }
  }
  return s;
}

InputSeparation worse_of(const InputSeparation& a, const InputSeparation& b) {
  InputSeparation s = a;
  s.condition = std::max(a.condition, b.condition);
  for (Eigen::Index i = 0; i < s.independent.size(); ++i) {
    if (b.independent(i) < a.independent(i)) {
      s.independent(i) = b.independent(i);
      s.regression.col(i) = b.regression.col(i);
    }
  }
  return s;
}

}  // namespace excite::host
