// SPDX-License-Identifier: MIT
#include "sim/column/block_tridiagonal.hpp"

namespace excite::sim::column {

Eigen::MatrixXd JacobianBlocks::dense() const {
  const Eigen::Index n = stages();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto idx = static_cast<std::size_t>(k);
    j.block<2, 2>(2 * k, 2 * k) = diag[idx];
    if (k > 0) j.block<2, 2>(2 * k, 2 * (k - 1)) = lower[idx];
    if (k + 1 < n) j.block<2, 2>(2 * k, 2 * (k + 1)) = upper[idx];
  }
  return j;
}

void BlockTridiagonalSolver::factorise_blocks(double shift) {
  const std::size_t n = blocks_.diag.size();
  const Eigen::Matrix2d shift_i = shift * Eigen::Matrix2d::Identity();
  pivot_inv_[0] = (shift_i - blocks_.diag[0]).inverse();
  for (std::size_t k = 1; k < n; ++k) {
    // A_k = shift·I − D_k, C_k = −L_k, B_{k−1} = −U_{k−1}:  W_k = A_k − C_k W_{k−1}⁻¹ B_{k−1}.
    elim_[k] = -blocks_.lower[k] * pivot_inv_[k - 1];
    const Eigen::Matrix2d pivot = shift_i - blocks_.diag[k] + elim_[k] * blocks_.upper[k - 1];
    pivot_inv_[k] = pivot.inverse();
  }
}

void BlockTridiagonalSolver::solve(Eigen::VectorXd& rhs) const {
  const std::size_t n = blocks_.diag.size();
  auto seg = [&rhs](std::size_t k) { return rhs.segment<2>(2 * static_cast<Eigen::Index>(k)); };
  for (std::size_t k = 1; k < n; ++k) seg(k) -= elim_[k] * seg(k - 1);
  seg(n - 1) = pivot_inv_[n - 1] * seg(n - 1);
  for (std::size_t k = n - 1; k-- > 0;) {
    // B_k = −U_k, so y_k − B_k g_{k+1} = y_k + U_k g_{k+1}.
    const Eigen::Vector2d y = seg(k) + blocks_.upper[k] * seg(k + 1);
    seg(k) = pivot_inv_[k] * y;
  }
}

void HoldupFirstSolver::factorise_blocks(double shift) {
  const Eigen::Index n = blocks_.stages();
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto b = static_cast<std::size_t>(k);
    const Eigen::Matrix2d& d = blocks_.diag[b];
    m_inv_[k] = 1.0 / (shift - d(1, 1));
    xm_diag_[k] = d(0, 1);
    const bool has_up = k + 1 < n;
    m_up_[k] = has_up ? blocks_.upper[b](1, 1) : 0.0;
    xm_up_[k] = has_up ? blocks_.upper[b](0, 1) : 0.0;
    x_up_[k] = has_up ? blocks_.upper[b](0, 0) : 0.0;
    // Thomas algorithm on (shift − J_xx): sub-diagonal −J_x,j−1, super-diagonal −J_x,j+1.
    double pivot = shift - d(0, 0);
    if (k > 0) {
      x_elim_[k] = -blocks_.lower[b](0, 0) * x_inv_[k - 1];
      pivot += x_elim_[k] * x_up_[k - 1];
    }
    x_inv_[k] = 1.0 / pivot;
  }
}

void HoldupFirstSolver::solve(Eigen::VectorXd& rhs) const {
  const Eigen::Index n = blocks_.stages();
  double* r = rhs.data();
  // Holdups: upper bidiagonal, back substitution from the top stage down.
  r[2 * n - 1] *= m_inv_[n - 1];
  for (Eigen::Index k = n - 1; k-- > 0;) {
    r[2 * k + 1] = (r[2 * k + 1] + m_up_[k] * r[2 * k + 3]) * m_inv_[k];
  }
  // Compositions: move the now known holdup terms to the right, then the tridiagonal sweep.
  r[0] += xm_diag_[0] * r[1] + xm_up_[0] * r[3];
  for (Eigen::Index k = 1; k < n; ++k) {
    const double up = k + 1 < n ? xm_up_[k] * r[2 * k + 3] : 0.0;
    r[2 * k] += xm_diag_[k] * r[2 * k + 1] + up - x_elim_[k] * r[2 * k - 2];
  }
  r[2 * n - 2] *= x_inv_[n - 1];
  for (Eigen::Index k = n - 1; k-- > 0;) {
    r[2 * k] = (r[2 * k] + x_up_[k] * r[2 * k + 2]) * x_inv_[k];
  }
}

}  // namespace excite::sim::column
