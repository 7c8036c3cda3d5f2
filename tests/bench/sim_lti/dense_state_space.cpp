// SPDX-License-Identifier: MIT
#include "dense_state_space.hpp"

#include <algorithm>
#include <vector>

namespace excite::bench {

DenseStateSpace::DenseStateSpace(const sim::DiscretePlant& plant) {
  const int n = plant.inputs();
  const int p = plant.outputs();
  // Delay registers: r_j,i = u_j(k − i), i = 1…D_j; then each section's TDF-II states.
  std::vector<Eigen::Index> longest(static_cast<std::size_t>(n), 0);
  Eigen::Index section_states = 0;
  for (const auto& s : plant.sections()) {
    auto& l = longest[static_cast<std::size_t>(s.in)];
    l = std::max<Eigen::Index>(l, s.term.delay_samples);
    section_states += s.term.order();
  }
  std::vector<Eigen::Index> reg(static_cast<std::size_t>(n));
  Eigen::Index nx = 0;
  for (int j = 0; j < n; ++j) {
    reg[static_cast<std::size_t>(j)] = nx;
    nx += longest[static_cast<std::size_t>(j)];
  }
  const Eigen::Index first_section = nx;
  nx += section_states;
  a_ = Eigen::MatrixXd::Zero(nx, nx);
  b_ = Eigen::MatrixXd::Zero(nx, n);
  c_ = Eigen::MatrixXd::Zero(p, nx);
  d_ = Eigen::MatrixXd::Zero(p, n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Index r = reg[static_cast<std::size_t>(j)];
    const Eigen::Index len = longest[static_cast<std::size_t>(j)];
    if (len == 0) continue;
    b_(r, j) = 1.0;
    for (Eigen::Index i = 1; i < len; ++i) a_(r + i, r + i - 1) = 1.0;
  }
  Eigen::Index at = first_section;
  for (const auto& s : plant.sections()) {
    const sim::DiscreteTerm& d = s.term;
    // w = E x + F u: the delayed input of this section.
    Eigen::RowVectorXd e = Eigen::RowVectorXd::Zero(nx);
    Eigen::RowVectorXd f = Eigen::RowVectorXd::Zero(n);
    if (d.delay_samples == 0) {
      f(s.in) = 1.0;
    } else {
      e(reg[static_cast<std::size_t>(s.in)] + d.delay_samples - 1) = 1.0;
    }
    const int order = d.order();
    const double b0 = d.b[0];
    // y = s0 + b0 w;  s_i⁺ = −a_{i+1} s0 + s_{i+1} + (b_{i+1} − a_{i+1} b0) w.
    c_.row(s.out) += b0 * e;
    d_.row(s.out) += b0 * f;
    if (order > 0) c_(s.out, at) += 1.0;
    for (int i = 0; i < order; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      a_(at + i, at) += -d.a[ui + 1];
      if (i + 1 < order) a_(at + i, at + i + 1) += 1.0;
      const double g = d.b[ui + 1] - d.a[ui + 1] * b0;
      a_.row(at + i) += g * e;
      b_.row(at + i) += g * f;
    }
    at += order;
  }
}

Eigen::MatrixXd DenseStateSpace::simulate(const Eigen::MatrixXd& u) const {
  Eigen::MatrixXd y(u.rows(), c_.rows());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(a_.rows());
  Eigen::VectorXd uk(u.cols());
  for (Eigen::Index k = 0; k < u.rows(); ++k) {
    uk = u.row(k).transpose();
    y.row(k) = (c_ * x + d_ * uk).transpose();
    x = a_ * x +
        b_ * uk;  // Eigen evaluates into a temporary: allocation per sample, as naive code does
  }
  return y;
}

}  // namespace excite::bench
