// SPDX-License-Identifier: MIT
#include "host/identify/miso_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "host/identify/bounded_lm.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kPerElement = 4;  // K, T_d, T_p1, T_p2 (Parameter order)

TwoPoleDelay unit_element(const Eigen::VectorXd& x, Eigen::Index e) {
  const Eigen::Index o = kPerElement * e;
  return TwoPoleDelay{1.0, x(o + kDelay), x(o + kTp1), x(o + kTp2)};
}

// The row's simulation: unit-gain responses per element, scaled and summed.
class RowModel {
 public:
  RowModel(const Eigen::MatrixXd& U, const std::vector<int>& inputs, double T_min)
      : U_(U), inputs_(inputs), T_(T_min), N_(static_cast<std::size_t>(U.rows())) {}

  void unit_response(Eigen::Index e, const TwoPoleDelay& g, double* out) const {
    simulate(discretise(g, T_), U_.col(inputs_[static_cast<std::size_t>(e)]).data(), 1, out, 1, N_);
  }

  Eigen::VectorXd output(const Eigen::VectorXd& x) const {
    Eigen::VectorXd y_hat = Eigen::VectorXd::Zero(U_.rows());
    Eigen::VectorXd z(U_.rows());
    for (Eigen::Index e = 0; e < elements(); ++e) {
      unit_response(e, unit_element(x, e), z.data());
      y_hat += x(kPerElement * e + kGain) * z;
    }
    return y_hat;
  }

  // ∂ŷ/∂x: gain columns exactly (the unit response), the others by central differences
  // (one-sided on a bound), each element simulated alone.
  void jacobian(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                const Eigen::VectorXd& upper, Eigen::MatrixXd& J) const {
    J.resize(U_.rows(), x.size());
    Eigen::VectorXd plus(U_.rows());
    Eigen::VectorXd minus(U_.rows());
    for (Eigen::Index e = 0; e < elements(); ++e) {
      const Eigen::Index o = kPerElement * e;
      const TwoPoleDelay g = unit_element(x, e);
      unit_response(e, g, J.col(o + kGain).data());
      for (const int m : {kDelay, kTp1, kTp2}) {
        const double v = x(o + m);
        const double h = 1e-6 * std::max(std::abs(v), T_);
        const double hi = std::min(v + h, upper(o + m));
        const double lo = std::max(v - h, lower(o + m));
        TwoPoleDelay gp = g;
        TwoPoleDelay gm = g;
        double* fields_p[] = {nullptr, &gp.delay_min, &gp.tp1_min, &gp.tp2_min};
        double* fields_m[] = {nullptr, &gm.delay_min, &gm.tp1_min, &gm.tp2_min};
        *fields_p[m] = hi;
        *fields_m[m] = lo;
        unit_response(e, gp, plus.data());
        unit_response(e, gm, minus.data());
        J.col(o + m) = (x(o + kGain) / (hi - lo)) * (plus - minus);
      }
    }
  }

  Eigen::Index elements() const { return static_cast<Eigen::Index>(inputs_.size()); }

 private:
  const Eigen::MatrixXd& U_;
  const std::vector<int>& inputs_;
  double T_;
  std::size_t N_;
};

// 1σ standard errors σ̂ √diag((JᵀJ)⁻¹) over the parameters not on a bound; inf for
// parameters in a direction the data do not determine (a numerically zero eigenvalue).
Eigen::VectorXd standard_errors(const Eigen::MatrixXd& J, double sse,
                                const std::vector<bool>& on_bound) {
  const Eigen::Index P = J.cols();
  Eigen::VectorXd se = Eigen::VectorXd::Constant(P, kNaN);
  std::vector<Eigen::Index> free;
  for (Eigen::Index m = 0; m < P; ++m) {
    if (!on_bound[static_cast<std::size_t>(m)]) free.push_back(m);
  }
  const auto F = static_cast<Eigen::Index>(free.size());
  const Eigen::Index dof = J.rows() - F;
  if (F == 0 || dof <= 0) return se;
  Eigen::MatrixXd Jf(J.rows(), F);
  for (Eigen::Index a = 0; a < F; ++a) Jf.col(a) = J.col(free[static_cast<std::size_t>(a)]);
  // Scale columns to unit norm so the eigen test is about directions, not units.
  Eigen::VectorXd norms = Jf.colwise().norm().transpose();
  for (Eigen::Index a = 0; a < F; ++a) {
    if (norms(a) == 0.0) norms(a) = 1.0;
  }
  const Eigen::MatrixXd Js = Jf * norms.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Js.transpose() * Js);
  const Eigen::VectorXd& lam = eig.eigenvalues();
  const Eigen::MatrixXd& V = eig.eigenvectors();
  const double sigma2 = sse / static_cast<double>(dof);
  const double floor = 1e-13 * std::max(lam.maxCoeff(), 0.0);
  for (Eigen::Index a = 0; a < F; ++a) {
    double var = 0.0;
    for (Eigen::Index k = 0; k < F; ++k) {
      const double w = V(a, k) * V(a, k);
      if (lam(k) <= floor) {
        if (w > 1e-12) var = kInf;
      } else {
        var += w / lam(k);
      }
    }
    se(free[static_cast<std::size_t>(a)]) = std::sqrt(sigma2 * var) / norms(a);
  }
  return se;
}

}  // namespace

MisoResult fit_miso(const Eigen::MatrixXd& U, const Eigen::VectorXd& y,
                    const std::vector<int>& inputs, std::vector<TwoPoleDelay> initial, double T_min,
                    const MisoBounds& bounds, int max_iterations) {
  const RowModel row(U, inputs, T_min);
  const Eigen::Index m = row.elements();
  const Eigen::Index P = kPerElement * m;

  LmProblem problem;
  problem.lower.resize(P);
  problem.upper.resize(P);
  problem.scale.resize(P);
  Eigen::VectorXd x0(P);
  for (Eigen::Index e = 0; e < m; ++e) {
    const Eigen::Index o = kPerElement * e;
    const TwoPoleDelay& g = initial[static_cast<std::size_t>(e)];
    x0.segment<kPerElement>(o) << g.gain, g.delay_min, g.tp1_min, g.tp2_min;
    problem.lower.segment<kPerElement>(o) << -kInf, 0.0, 0.0, 0.0;
    problem.upper.segment<kPerElement>(o) << kInf, bounds.max_delay_min,
        bounds.max_time_constant_min, bounds.max_time_constant_min;
    problem.scale.segment<kPerElement>(o) << std::max(std::abs(g.gain), 1e-12), T_min, T_min, T_min;
  }
  problem.residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r = y - row.output(x);
    return true;
  };
  problem.jacobian = [&](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    row.jacobian(x, problem.lower, problem.upper, J);
  };
  LmOptions lm_options;
  lm_options.max_iterations = max_iterations;
  const LmResult lm = minimise_bounded(problem, x0, lm_options);

  MisoResult out;
  out.iterations = lm.iterations;
  out.converged = lm.converged;
  out.y_hat = row.output(lm.x);
  Eigen::MatrixXd J;
  row.jacobian(lm.x, problem.lower, problem.upper, J);
  std::vector<bool> on_bound(static_cast<std::size_t>(P));
  for (Eigen::Index k = 0; k < P; ++k) {
    on_bound[static_cast<std::size_t>(k)] =
        lm.x(k) <= problem.lower(k) || lm.x(k) >= problem.upper(k);
  }
  const Eigen::VectorXd se = standard_errors(J, lm.cost, on_bound);

  for (Eigen::Index e = 0; e < m; ++e) {
    const Eigen::Index o = kPerElement * e;
    ElementEstimate est;
    est.value = TwoPoleDelay{lm.x(o), lm.x(o + 1), lm.x(o + 2), lm.x(o + 3)};
    est.std_error = TwoPoleDelay{se(o), se(o + 1), se(o + 2), se(o + 3)};
    for (int k = 0; k < kPerElement; ++k)
      est.at_bound[static_cast<std::size_t>(k)] = on_bound[static_cast<std::size_t>(o + k)];
    // Report T_p1 ≥ T_p2 (the model is symmetric in them).
    if (est.value.tp2_min > est.value.tp1_min) {
      std::swap(est.value.tp1_min, est.value.tp2_min);
      std::swap(est.std_error.tp1_min, est.std_error.tp2_min);
      std::swap(est.at_bound[kTp1], est.at_bound[kTp2]);
    }
    const double k_se = est.std_error.gain;
    if (std::isfinite(k_se) ? std::abs(est.value.gain) < 2.0 * k_se : std::isinf(k_se)) {
      est.status = ElementStatus::weak_gain;
      char buf[220];
      std::snprintf(buf, sizeof buf,
                    "|K| = %.3g is below two standard errors (%.3g): the data barely show this "
                    "element, its delay and time constants are not determined",
                    std::abs(est.value.gain), k_se);
      est.reason = buf;
    }
    out.elements.push_back(est);
  }
  return out;
}

}  // namespace excite::host
