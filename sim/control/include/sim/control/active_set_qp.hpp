// SPDX-License-Identifier: MIT
#pragma once
// A small dense convex QP, solved exactly by a dual active-set method (Goldfarb and Idnani,
// Math. Programming 27 (1983) 1):
//
//   minimise ½ xᵀH x + gᵀx   subject to   A x ≤ b,
//
// H (nv × nv, positive definite) and A (m × nv) fixed at construction, g and b new at every
// solve — the shape of a DMC step (the matrices come from the step-response model and the
// weights, the vectors from the free response, setpoints and limits).
//
// Why this method (sim/control/README.md, "The QP"): the problems are small and dense
// (nv = n·M moves plus a slack per CV), a dual method needs no feasible starting point
// (it starts at the unconstrained minimum, so with no constraint violated the solve is the
// unconstrained law, one pass over the constraints), it ends after finitely many steps
// with the exact optimum (each step adds or drops one constraint; the dual objective
// rises), and it starts warm from the previous sample's active set.
//
// Construction factors H = L Lᵀ and keeps C = L⁻¹Aᵀ; a solve works in ξ = Lᵀx, where the
// Hessian is the identity. solve() allocates nothing and throws nothing; its work is
// bounded by `max_iterations` passes of O(m·nv + nv³).

#include <Eigen/Dense>

#include <cstdint>
#include <span>
#include <vector>

namespace excite::sim::control {

enum class QpStatus : std::uint8_t {
  optimal,
  infeasible,       // the constraints exclude every x (x is then the last iterate)
  iteration_limit,  // stopped at max_iterations (x is then not feasible in general)
};

struct QpResult {
  QpStatus status = QpStatus::optimal;
  int iterations = 0;  // constraints added or dropped (warm start's drops included)
  int active = 0;      // size of the final active set
};

class ActiveSetQp {
 public:
  /// Throws std::invalid_argument naming H or A: sizes, non-finite values, H not positive
  /// definite, a row of A that is all zeros.
  ActiveSetQp(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, int max_iterations);

  int variables() const noexcept { return static_cast<int>(L_.rows()); }
  int constraints() const noexcept { return static_cast<int>(C_.cols()); }

  /// Solves for g (nv) and b (m) into x (nv), starting from the active set of the last
  /// solve (empty at first and after forget()). Sizes are the caller's contract (checked
  /// only by assertions of Eigen in debug builds).
  QpResult solve(const Eigen::Ref<const Eigen::VectorXd>& g,
                 const Eigen::Ref<const Eigen::VectorXd>& b,
                 Eigen::Ref<Eigen::VectorXd> x) noexcept;

  /// The next solve starts cold (from the unconstrained minimum).
  void forget() noexcept;

  /// Indices (rows of A) active at the last solution, and their multipliers λ ≥ 0 (KKT:
  /// H x + g + Aᵀλ = 0 over these rows).
  std::span<const int> active_set() const noexcept {
    return {active_.data(), static_cast<std::size_t>(active_count_)};
  }
  std::span<const double> multipliers() const noexcept {
    return {lambda_.data(), static_cast<std::size_t>(active_count_)};
  }

 private:
  // Solves (C_Aᵀ C_A) out = rhs for the current active set (Cholesky of the Gram matrix);
  // false when it is numerically singular.
  bool solve_gram(const double* rhs, double* out) noexcept;
  // ξ = −h − C_A λ for the multipliers in lambda_ (the S-pair's point).
  void point_from_multipliers() noexcept;
  void drop(int position) noexcept;

  Eigen::MatrixXd L_;         // H = L Lᵀ (lower)
  Eigen::MatrixXd C_;         // L⁻¹ Aᵀ, nv × m
  Eigen::VectorXd row_norm_;  // ‖C_j‖: the violation of row j is measured in ξ-space distance
  int max_iterations_;

  // Work space, sized at construction.
  Eigen::VectorXd h_;      // L⁻¹ g
  Eigen::VectorXd xi_;     // Lᵀ x
  Eigen::VectorXd slack_;  // b − C ᵀξ
  Eigen::VectorXd d_;      // step direction in ξ-space
  Eigen::MatrixXd gram_;   // Cholesky factor of C_Aᵀ C_A, nv × nv used top-left
  Eigen::VectorXd rhs_, r_;
  Eigen::VectorXi active_;                // the active rows, active_count_ of them used
  std::vector<unsigned char> is_active_;  // per row: in active_ (never picked as violated)
  Eigen::VectorXd lambda_;
  int active_count_ = 0;
};

}  // namespace excite::sim::control
