// SPDX-License-Identifier: MIT
#pragma once
// Linear solver for the Rosenbrock stages of a column whose state is ordered stage by stage
// as (x_j, M_j): the Jacobian is then block tridiagonal with 2×2 blocks (stage j couples
// only to stages j−1 and j+1). Factorises shift·I − J by block LU without pivoting, O(n):
// with shift = 1/(γh) > 0 and the column Jacobian's weak block diagonal dominance the
// pivots stay well conditioned.
//
// System: void jacobian_blocks(const Eigen::VectorXd& s, JacobianBlocks& out) const;

#include <Eigen/Dense>
#include <vector>

namespace excite::sim::column {

/// J in block form: lower[j] = ∂f_j/∂s_{j−1} (lower[0] unused), diag[j] = ∂f_j/∂s_j,
/// upper[j] = ∂f_j/∂s_{j+1} (upper[stages−1] unused); f_j and s_j are stage j's pair.
struct JacobianBlocks {
  explicit JacobianBlocks(Eigen::Index stages)
      : lower(static_cast<std::size_t>(stages), Eigen::Matrix2d::Zero()),
        diag(static_cast<std::size_t>(stages), Eigen::Matrix2d::Zero()),
        upper(static_cast<std::size_t>(stages), Eigen::Matrix2d::Zero()) {}
  std::vector<Eigen::Matrix2d> lower, diag, upper;

  Eigen::Index stages() const { return static_cast<Eigen::Index>(diag.size()); }
  /// The same Jacobian as a dense 2·stages square matrix.
  Eigen::MatrixXd dense() const;
};

class BlockTridiagonalSolver {
 public:
  explicit BlockTridiagonalSolver(Eigen::Index stages)
      : blocks_(stages),
        pivot_inv_(static_cast<std::size_t>(stages)),
        elim_(static_cast<std::size_t>(stages)) {}

  template <class System>
  void factorise(const System& sys, const Eigen::VectorXd& s, double shift) {
    sys.jacobian_blocks(s, blocks_);
    factorise_blocks(shift);
  }

  /// Solves (shift·I − J) g = rhs in place.
  void solve(Eigen::VectorXd& rhs) const;

 private:
  void factorise_blocks(double shift);

  JacobianBlocks blocks_;
  std::vector<Eigen::Matrix2d> pivot_inv_;  // inverse of the j-th block pivot
  std::vector<Eigen::Matrix2d> elim_;       // (−lower_j)·pivot_inv_{j−1}
};

/// The same system when the holdups do not depend on the compositions (constant molar
/// flows, as in column A): with state (x_j, M_j) per stage, every block has a zero (1, 0)
/// entry and the lower blocks only a (0, 0) entry. Then shift·I − J is block triangular in
/// (M, x): the holdup part is upper bidiagonal and the composition part tridiagonal, and
/// the solve is two scalar sweeps instead of a 2×2 block recursion (about half the work
/// of BlockTridiagonalSolver on the Rosenbrock stages). Precondition (not checked per
/// call; the unit tests check colaA's Jacobian has this structure): the zero pattern above.
class HoldupFirstSolver {
 public:
  explicit HoldupFirstSolver(Eigen::Index stages)
      : blocks_(stages),
        m_inv_(stages),
        m_up_(stages),
        x_up_(stages),
        x_inv_(stages),
        x_elim_(stages),
        xm_diag_(stages),
        xm_up_(stages) {}

  template <class System>
  void factorise(const System& sys, const Eigen::VectorXd& s, double shift) {
    sys.jacobian_blocks(s, blocks_);
    factorise_blocks(shift);
  }

  /// Solves (shift·I − J) g = rhs in place.
  void solve(Eigen::VectorXd& rhs) const;

 private:
  void factorise_blocks(double shift);

  JacobianBlocks blocks_;
  Eigen::VectorXd m_inv_;    // 1 / (shift − ∂Ṁ_j/∂M_j)
  Eigen::VectorXd m_up_;     // ∂Ṁ_j/∂M_{j+1}
  Eigen::VectorXd x_up_;     // ∂ẋ_j/∂x_{j+1}
  Eigen::VectorXd x_inv_;    // 1 / pivot of the composition sweep
  Eigen::VectorXd x_elim_;   // ∂ẋ_j/∂x_{j−1} · x_inv_{j−1}
  Eigen::VectorXd xm_diag_;  // ∂ẋ_j/∂M_j
  Eigen::VectorXd xm_up_;    // ∂ẋ_j/∂M_{j+1}
};

}  // namespace excite::sim::column
