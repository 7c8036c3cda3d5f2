// SPDX-License-Identifier: MIT
#include "host/identify/gain_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace excite::host {
namespace {

struct Svd {
  Eigen::VectorXd s;
  Eigen::MatrixXd U, V;
};

Svd svd_of(const Eigen::MatrixXd& G) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return {svd.singularValues(), svd.matrixU(), svd.matrixV()};
}

// Flips the singular vectors of `b` to point as those of `a` do (the SVD fixes them only up
// to a common sign per pair).
void align(const Svd& a, Svd& b) {
  for (Eigen::Index i = 0; i < a.s.size(); ++i) {
    if (a.V.col(i).dot(b.V.col(i)) < 0.0) {
      b.V.col(i) *= -1.0;
      b.U.col(i) *= -1.0;
    }
  }
}

// Σ over rows j of gᵀ C_j g, g the gradient restricted to row j's gains.
double propagate(const Eigen::MatrixXd& gradient, const std::vector<Eigen::MatrixXd>& cov) {
  double variance = 0.0;
  for (Eigen::Index j = 0; j < gradient.rows(); ++j) {
    const Eigen::VectorXd g = gradient.row(j).transpose();
    variance += g.dot(cov[static_cast<std::size_t>(j)] * g);
  }
  return variance;
}

}  // namespace

GainUncertainty gain_uncertainty(const Eigen::MatrixXd& G,
                                 const std::vector<Eigen::MatrixXd>& row_covariance) {
  const Eigen::Index p = G.rows(), n = G.cols();
  if (p == 0 || n == 0 || static_cast<Eigen::Index>(row_covariance.size()) != p) {
    throw std::invalid_argument("gain_uncertainty: " + std::to_string(row_covariance.size()) +
                                " row covariances for a " + std::to_string(p) + " x " +
                                std::to_string(n) + " gain, expected one per row");
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    const Eigen::MatrixXd& c = row_covariance[static_cast<std::size_t>(j)];
    if (c.rows() != n || c.cols() != n || !c.allFinite() || !G.row(j).allFinite()) {
      throw std::invalid_argument("gain_uncertainty: row " + std::to_string(j + 1) +
                                  ": gains or their covariance not finite or not " +
                                  std::to_string(n) + " x " + std::to_string(n));
    }
  }
  const Svd base = svd_of(G);
  const Eigen::Index r = base.s.size();
  // Central differences in every gain: derivatives of σ_i, v_i, w_i. The step is 1e-6 of
  // the largest gain: small against every gap between singular values that matters.
  const double h = 1e-6 * std::max(G.cwiseAbs().maxCoeff(), 1e-300);
  std::vector<Eigen::MatrixXd> d_sigma(static_cast<std::size_t>(r), Eigen::MatrixXd::Zero(p, n));
  std::vector<std::vector<Eigen::MatrixXd>> d_v(static_cast<std::size_t>(r)),
      d_w(static_cast<std::size_t>(r));
  for (Eigen::Index i = 0; i < r; ++i) {
    d_v[static_cast<std::size_t>(i)].assign(static_cast<std::size_t>(n),
                                            Eigen::MatrixXd::Zero(p, n));
    d_w[static_cast<std::size_t>(i)].assign(static_cast<std::size_t>(p),
                                            Eigen::MatrixXd::Zero(p, n));
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    for (Eigen::Index k = 0; k < n; ++k) {
      Eigen::MatrixXd up = G, down = G;
      up(j, k) += h;
      down(j, k) -= h;
      Svd a = svd_of(up), b = svd_of(down);
      align(base, a);
      align(base, b);
      for (Eigen::Index i = 0; i < r; ++i) {
        const auto si = static_cast<std::size_t>(i);
        d_sigma[si](j, k) = (a.s(i) - b.s(i)) / (2 * h);
        for (Eigen::Index m = 0; m < n; ++m) {
          d_v[si][static_cast<std::size_t>(m)](j, k) = (a.V(m, i) - b.V(m, i)) / (2 * h);
        }
        for (Eigen::Index m = 0; m < p; ++m) {
          d_w[si][static_cast<std::size_t>(m)](j, k) = (a.U(m, i) - b.U(m, i)) / (2 * h);
        }
      }
    }
  }
  constexpr double kDegrees = 180.0 / std::numbers::pi;
  GainUncertainty out;
  out.singular_values = base.s;
  out.singular_value_se.resize(r);
  out.input_angle_se_deg.resize(r);
  out.output_angle_se_deg.resize(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const auto si = static_cast<std::size_t>(i);
    out.singular_value_se(i) = std::sqrt(propagate(d_sigma[si], row_covariance));
    double v_var = 0.0, w_var = 0.0;  // E‖δv‖² = Σ_m Var(v_m): δv ⟂ v to first order
    for (const auto& g : d_v[si]) v_var += propagate(g, row_covariance);
    for (const auto& g : d_w[si]) w_var += propagate(g, row_covariance);
    out.input_angle_se_deg(i) = kDegrees * std::sqrt(v_var);
    out.output_angle_se_deg(i) = kDegrees * std::sqrt(w_var);
  }
  if (p != n) return out;
  // Principal minors: ∂det(A)/∂A = cofactors, by the same central differences.
  for (unsigned mask = 1; mask < (1U << n); ++mask) {
    PrincipalMinor minor;
    for (Eigen::Index k = 0; k < n; ++k) {
      if ((mask >> k) & 1U) minor.rows.push_back(static_cast<int>(k));
    }
    const auto m = static_cast<Eigen::Index>(minor.rows.size());
    const auto det_of = [&](const Eigen::MatrixXd& A) {
      Eigen::MatrixXd sub(m, m);
      for (Eigen::Index a = 0; a < m; ++a) {
        for (Eigen::Index b = 0; b < m; ++b) {
          sub(a, b) =
              A(minor.rows[static_cast<std::size_t>(a)], minor.rows[static_cast<std::size_t>(b)]);
        }
      }
      return sub.determinant();
    };
    minor.value = det_of(G);
    Eigen::MatrixXd gradient = Eigen::MatrixXd::Zero(p, n);
    for (const int j : minor.rows) {
      for (const int k : minor.rows) {
        Eigen::MatrixXd up = G, down = G;
        up(j, k) += h;
        down(j, k) -= h;
        gradient(j, k) = (det_of(up) - det_of(down)) / (2 * h);
      }
    }
    minor.std_error = std::sqrt(propagate(gradient, row_covariance));
    minor.sign_uncertain = std::abs(minor.value) < 1.96 * minor.std_error;
    out.sign_uncertain_minors += minor.sign_uncertain ? 1 : 0;
    out.principal_minors.push_back(std::move(minor));
  }
  std::stable_sort(out.principal_minors.begin(), out.principal_minors.end(),
                   [](const PrincipalMinor& a, const PrincipalMinor& b) {
                     return a.rows.size() < b.rows.size();
                   });
  return out;
}

}  // namespace excite::host
