// SPDX-License-Identifier: MIT
#include "sim/control/active_set_qp.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace excite::sim::control {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// A constraint is violated when b − aᵀx < −kFeasibilityTolerance·(1 + |b|).
constexpr double kFeasibilityTolerance = 1e-9;
// A new constraint's normal counts as dependent on the active ones when its part outside
// their span is below this fraction of its length (squared).
constexpr double kDependenceTolerance = 1e-12;

void refuse(const std::string& field, const std::string& value, const std::string& expected) {
  throw std::invalid_argument(field + " = " + value + ", expected " + expected);
}

}  // namespace

ActiveSetQp::ActiveSetQp(const Eigen::MatrixXd& H, const Eigen::MatrixXd& A, int max_iterations)
    : max_iterations_(max_iterations) {
  const Eigen::Index nv = H.rows();
  if (nv < 1 || H.cols() != nv) {
    refuse("H", std::to_string(H.rows()) + "×" + std::to_string(H.cols()),
           "a square matrix with at least one row");
  }
  if (A.cols() != nv) {
    refuse("A", std::to_string(A.rows()) + "×" + std::to_string(A.cols()),
           std::to_string(nv) + " columns (one per variable)");
  }
  if (!H.allFinite()) refuse("H", "(a non-finite entry)", "finite entries");
  if (!A.allFinite()) refuse("A", "(a non-finite entry)", "finite entries");
  if (max_iterations < 1) refuse("max_iterations", std::to_string(max_iterations), "at least 1");
  const Eigen::MatrixXd symmetric = 0.5 * (H + H.transpose());
  Eigen::LLT<Eigen::MatrixXd> llt(symmetric);
  const double smallest_pivot =
      llt.info() == Eigen::Success ? llt.matrixL().toDenseMatrix().diagonal().minCoeff() : 0.0;
  if (llt.info() != Eigen::Success ||
      !(smallest_pivot > 1e-10 * std::sqrt(symmetric.diagonal().maxCoeff()))) {
    refuse("H", "(not positive definite)", "a positive definite Hessian (every move weighted)");
  }
  L_ = llt.matrixL();
  // No constraint: nothing to solve (Eigen's triangular solve binds a reference to the first
  // coefficient of an empty right-hand side, which UBSan refuses).
  C_ = A.rows() == 0 ? Eigen::MatrixXd(L_.rows(), 0)
                     : Eigen::MatrixXd(L_.triangularView<Eigen::Lower>().solve(A.transpose()));
  row_norm_ = C_.colwise().norm().transpose();
  for (Eigen::Index j = 0; j < A.rows(); ++j) {
    if (!(row_norm_(j) > 0.0)) {
      refuse("A row " + std::to_string(j), "0", "a constraint that involves a variable");
    }
  }
  h_.setZero(nv);
  xi_.setZero(nv);
  slack_.setZero(A.rows());
  d_.setZero(nv);
  gram_.setZero(nv, nv);
  rhs_.setZero(nv);
  r_.setZero(nv);
  active_.setConstant(nv, -1);
  is_active_.assign(static_cast<std::size_t>(A.rows()), 0);
  lambda_.setZero(nv);
}

bool ActiveSetQp::solve_gram(const double* rhs, double* out) noexcept {
  const int q = active_count_;
  // Lower Cholesky factor of G = C_Aᵀ C_A, in gram_.
  for (int i = 0; i < q; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = C_.col(active_(i)).dot(C_.col(active_(j)));
      for (int k = 0; k < j; ++k) s -= gram_(i, k) * gram_(j, k);
      if (i == j) {
        if (!(s > kDependenceTolerance * C_.col(active_(i)).squaredNorm())) return false;
        gram_(i, i) = std::sqrt(s);
      } else {
        gram_(i, j) = s / gram_(j, j);
      }
    }
  }
  for (int i = 0; i < q; ++i) {  // forward: G_L w = rhs
    double s = rhs[i];
    for (int k = 0; k < i; ++k) s -= gram_(i, k) * out[k];
    out[i] = s / gram_(i, i);
  }
  for (int i = q - 1; i >= 0; --i) {  // backward: G_Lᵀ out = w
    double s = out[i];
    for (int k = i + 1; k < q; ++k) s -= gram_(k, i) * out[k];
    out[i] = s / gram_(i, i);
  }
  return true;
}

void ActiveSetQp::point_from_multipliers() noexcept {
  xi_ = -h_;
  for (int i = 0; i < active_count_; ++i) {
    xi_.noalias() -= lambda_(i) * C_.col(active_(i));
  }
}

void ActiveSetQp::forget() noexcept {
  for (int i = 0; i < active_count_; ++i) is_active_[static_cast<std::size_t>(active_(i))] = 0;
  active_count_ = 0;
}

void ActiveSetQp::drop(int position) noexcept {
  is_active_[static_cast<std::size_t>(active_(position))] = 0;
  for (int i = position; i + 1 < active_count_; ++i) {
    active_(i) = active_(i + 1);
    lambda_(i) = lambda_(i + 1);
  }
  --active_count_;
}

QpResult ActiveSetQp::solve(const Eigen::Ref<const Eigen::VectorXd>& g,
                            const Eigen::Ref<const Eigen::VectorXd>& b,
                            Eigen::Ref<Eigen::VectorXd> x) noexcept {
  const Eigen::Index nv = L_.rows();
  const Eigen::Index m = C_.cols();
  QpResult result;
  // h = L⁻¹ g (forward substitution).
  for (Eigen::Index i = 0; i < nv; ++i) {
    double s = g(i);
    for (Eigen::Index k = 0; k < i; ++k) s -= L_(i, k) * h_(k);
    h_(i) = s / L_(i, i);
  }

  // Warm start: the previous active set, less every constraint whose multiplier comes out
  // negative for this g and b (dropped one at a time, most negative first), is an S-pair:
  // ξ optimal subject to those constraints as equalities, λ ≥ 0.
  while (active_count_ > 0) {
    for (int i = 0; i < active_count_; ++i) {
      const int j = active_(i);
      rhs_(i) = -C_.col(j).dot(h_) - b(j);
    }
    if (!solve_gram(rhs_.data(), lambda_.data())) {
      forget();
      break;
    }
    int most_negative = -1;
    for (int i = 0; i < active_count_; ++i) {
      if (lambda_(i) < 0.0 && (most_negative < 0 || lambda_(i) < lambda_(most_negative))) {
        most_negative = i;
      }
    }
    if (most_negative < 0) break;
    drop(most_negative);
    ++result.iterations;
  }
  point_from_multipliers();

  const auto finish = [&](QpStatus status) {
    for (Eigen::Index i = nv - 1; i >= 0; --i) {  // x = L⁻ᵀ ξ (backward substitution)
      double s = xi_(i);
      for (Eigen::Index k = i + 1; k < nv; ++k) s -= L_(k, i) * x(k);
      x(i) = s / L_(i, i);
    }
    result.status = status;
    result.active = active_count_;
    return result;
  };

  while (true) {
    // The most violated constraint, by its distance in ξ-space.
    int p = -1;
    double worst = 0.0;
    for (Eigen::Index j = 0; j < m; ++j) {
      slack_(j) = b(j) - C_.col(j).dot(xi_);
      if (is_active_[static_cast<std::size_t>(j)] == 0 &&
          slack_(j) < -kFeasibilityTolerance * (1.0 + std::abs(b(j)))) {
        const double violation = -slack_(j) / row_norm_(j);
        if (violation > worst) {
          worst = violation;
          p = static_cast<int>(j);
        }
      }
    }
    if (p < 0) return finish(QpStatus::optimal);
    double slack_p = slack_(p);
    double lambda_p = 0.0;
    while (true) {
      if (result.iterations >= max_iterations_) return finish(QpStatus::iteration_limit);
      const int q = active_count_;
      for (int i = 0; i < q; ++i) {
        rhs_(i) = C_.col(active_(i)).dot(C_.col(p));
      }
      if (q > 0 && !solve_gram(rhs_.data(), r_.data())) return finish(QpStatus::infeasible);
      // d: −c_p projected on the null space of the active normals (keeps them active and
      // raises the slack of p); r: how the active multipliers fall per unit step.
      d_ = -C_.col(p);
      for (int i = 0; i < q; ++i) {
        d_.noalias() += r_(i) * C_.col(active_(i));
      }
      const double dd = d_.squaredNorm();
      const double full_step =
          q < nv && dd > kDependenceTolerance * C_.col(p).squaredNorm() ? -slack_p / dd : kInfinity;
      double partial_step = kInfinity;
      int blocking = -1;
      for (int i = 0; i < q; ++i) {
        const double ri = r_(i);
        if (ri > 0.0) {
          const double t = lambda_(i) / ri;
          if (t < partial_step) {
            partial_step = t;
            blocking = i;
          }
        }
      }
      if (full_step == kInfinity && partial_step == kInfinity) {
        return finish(QpStatus::infeasible);
      }
      const double t = full_step <= partial_step ? full_step : partial_step;
      if (full_step != kInfinity) {
        xi_.noalias() += t * d_;
        slack_p += t * dd;
      }
      for (int i = 0; i < q; ++i) {
        lambda_(i) -= t * r_(i);
      }
      lambda_p += t;
      ++result.iterations;
      if (full_step <= partial_step) {  // p becomes active
        active_(q) = p;
        is_active_[static_cast<std::size_t>(p)] = 1;
        lambda_(q) = lambda_p;
        ++active_count_;
        break;
      }
      lambda_(blocking) = 0.0;
      drop(blocking);
    }
  }
}

}  // namespace excite::sim::control
