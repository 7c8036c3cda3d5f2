// SPDX-License-Identifier: MIT
#include "host/identify/bounded_lm.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace excite::host {
namespace {

Eigen::VectorXd clamp(const Eigen::VectorXd& x, const LmProblem& p) {
  return x.cwiseMax(p.lower).cwiseMin(p.upper);
}

}  // namespace

void normal_matrix(const Eigen::MatrixXd& J, Eigen::MatrixXd& H) {
  const Eigen::Index P = J.cols();
  H.resize(P, P);
  for (Eigen::Index a = 0; a < P; ++a)
    H.col(a).head(a + 1).noalias() = J.leftCols(a + 1).transpose() * J.col(a);
  H.triangularView<Eigen::StrictlyLower>() = H.transpose();
}

LmResult minimise_bounded(const LmProblem& problem, Eigen::VectorXd x0, const LmOptions& options) {
  const Eigen::Index P = x0.size();
  LmResult out;
  out.x = clamp(x0, problem);
  Eigen::VectorXd r;
  problem.residual(out.x, r);
  out.cost = r.squaredNorm();
  const Eigen::Index dof = r.size() - P;

  Eigen::MatrixXd J;
  Eigen::VectorXd r_new;
  double lambda = 1e-3;
  double nu = 2.0;
  int small_reductions = 0;
  for (out.iterations = 0; out.iterations < options.max_iterations; ++out.iterations) {
    if (out.cost == 0.0) {
      out.converged = true;
      return out;
    }
    problem.jacobian(out.x, J);
    Eigen::MatrixXd H;
    normal_matrix(J, H);
    const Eigen::VectorXd g = J.transpose() * r;  // −½ ∇cost: the descent direction

    // Free parameters: not on a bound with the gradient pointing outwards.
    std::vector<Eigen::Index> free;
    for (Eigen::Index m = 0; m < P; ++m) {
      const bool held_low = out.x(m) <= problem.lower(m) && g(m) < 0.0;
      const bool held_high = out.x(m) >= problem.upper(m) && g(m) > 0.0;
      if (!held_low && !held_high) free.push_back(m);
    }
    if (free.empty()) {
      out.converged = true;
      return out;
    }
    const auto F = static_cast<Eigen::Index>(free.size());
    Eigen::MatrixXd Hf(F, F);
    Eigen::VectorXd gf(F);
    for (Eigen::Index a = 0; a < F; ++a) {
      gf(a) = g(free[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < F; ++b) {
        Hf(a, b) = H(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
      }
    }
    const double dmax = Hf.diagonal().maxCoeff();
    if (dmax <= 0.0) {
      out.converged = true;
      return out;
    }
    const Eigen::VectorXd D = Hf.diagonal().cwiseMax(1e-12 * dmax);

    bool accepted = false;
    while (!accepted) {
      Eigen::MatrixXd A = Hf;
      A.diagonal() += lambda * D;
      const Eigen::VectorXd df = A.ldlt().solve(gf);
      Eigen::VectorXd x_new = out.x;
      for (Eigen::Index a = 0; a < F; ++a) x_new(free[static_cast<std::size_t>(a)]) += df(a);
      x_new = clamp(x_new, problem);
      const Eigen::VectorXd step = x_new - out.x;

      const bool tiny = ((step.cwiseAbs().array()) <=
                         options.step_tolerance * (out.x.cwiseAbs() + problem.scale).array())
                            .all();
      const double predicted = 2.0 * step.dot(g) - step.dot(H * step);
      const bool ok = problem.residual(x_new, r_new) && std::isfinite(r_new.squaredNorm());
      const double cost_new = ok ? r_new.squaredNorm() : out.cost;
      if (ok && cost_new < out.cost) {
        const double rho = predicted > 0.0 ? (out.cost - cost_new) / predicted : 0.0;
        const double sigma2 = cost_new / static_cast<double>(std::max<Eigen::Index>(dof, 1));
        small_reductions =
            (out.cost - cost_new) <= options.cost_tolerance * sigma2 ? small_reductions + 1 : 0;
        out.x = x_new;
        std::swap(r, r_new);
        out.cost = cost_new;
        lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        nu = 2.0;
        accepted = true;
        if (tiny || small_reductions >= 2) {
          out.converged = true;
          ++out.iterations;
          return out;
        }
      } else {
        if (tiny || lambda > 1e16) {
          // No representable step lowers the cost: a (local) minimum within precision.
          out.converged = true;
          return out;
        }
        lambda *= nu;
        nu *= 2.0;
      }
    }
  }
  return out;
}

}  // namespace excite::host
