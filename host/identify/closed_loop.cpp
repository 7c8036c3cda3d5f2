// SPDX-License-Identifier: MIT
#include "host/identify/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace excite::host {

int default_stage1_lags(Eigen::Index rows, Eigen::Index channels) {
  return static_cast<int>(std::clamp<Eigen::Index>(rows / (8 * channels), 20, 200));
}

Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags) {
  const Eigen::Index N = U.rows();
  const Eigen::Index m = R.cols();
  if (R.rows() != N || m == 0 || U.cols() == 0) {
    throw std::invalid_argument("r rows x channels = " + std::to_string(R.rows()) + "x" +
                                std::to_string(m) + ", expected " + std::to_string(N) +
                                " rows (as u) and at least one channel");
  }
  if (!R.allFinite() || !U.allFinite()) {
    throw std::invalid_argument("u, r = (not finite), expected finite values");
  }
  if (R.cwiseAbs().maxCoeff() == 0.0) {
    throw std::invalid_argument(
        "r = 0 throughout, expected a test signal (the two-stage "
        "method needs r to explain u)");
  }
  if (lags == 0) {
    lags = default_stage1_lags(N, m);
  }
  const Eigen::Index P = static_cast<Eigen::Index>(lags) * m;
  if (lags < 1 || 2 * P >= N) {
    throw std::invalid_argument("stage-1 lags = " + std::to_string(lags) + " x " +
                                std::to_string(m) + " r channels, expected fewer than " +
                                std::to_string(N / 2) + " parameters for " + std::to_string(N) +
                                " rows");
  }
  // Φ (N × L·m): column l·m + c is r_c(k − l), 0 before row 0.
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(N, P);
  for (int l = 0; l < lags; ++l) {
    for (Eigen::Index c = 0; c < m; ++c) {
      phi.col(l * m + c).tail(N - l) = R.col(c).head(N - l);
    }
  }
  // Least squares by a column-pivoting QR (rank-revealing: an r channel that is zero or a
  // copy of another leaves columns the QR drops instead of dividing by zero).
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(phi);
  Stage1Fit fit;
  fit.lags = lags;
  fit.u_hat = phi * qr.solve(U);
  fit.fit_percent.resize(U.cols());
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    const double spread = (U.col(j).array() - U.col(j).mean()).matrix().norm();
    fit.fit_percent(j) =
        spread > 0.0 ? 100.0 * (1.0 - (U.col(j) - fit.u_hat.col(j)).norm() / spread) : std::nan("");
  }
  return fit;
}

std::vector<GainDisagreement> gain_disagreements(const IdentifiedModel& a, const IdentifiedModel& b,
                                                 double k) {
  if (a.inputs != b.inputs || a.outputs != b.outputs) {
    throw std::invalid_argument("model sizes = " + std::to_string(a.outputs) + "x" +
                                std::to_string(a.inputs) + " and " + std::to_string(b.outputs) +
                                "x" + std::to_string(b.inputs) + ", expected equal");
  }
  std::vector<GainDisagreement> out;
  for (int o = 0; o < a.outputs; ++o) {
    for (int i = 0; i < a.inputs; ++i) {
      const ElementEstimate& ea = a.element(o, i);
      const ElementEstimate& eb = b.element(o, i);
      if (!ea.estimated() || !eb.estimated()) continue;
      const double sa = ea.std_error.gain, sb = eb.std_error.gain;
      if (!std::isfinite(sa) || !std::isfinite(sb)) continue;
      const double sigma = std::sqrt(sa * sa + sb * sb);
      const double ka = ea.value.static_gain(), kb = eb.value.static_gain();
      if (std::isfinite(ka) && std::isfinite(kb) && std::abs(ka - kb) > k * sigma) {
        out.push_back({o, i, ka, kb, sigma});
      }
    }
  }
  return out;
}

double widen_for_coloured_residuals(IdentificationResult& result, const Eigen::MatrixXd& U,
                                    const Eigen::MatrixXd& Y, const SampleLayout& layout,
                                    int max_lag) {
  IdentifiedModel& model = result.model;
  const Eigen::Index N = U.rows();
  const int n = model.inputs;
  const Eigen::Index L =
      max_lag > 0 ? max_lag : std::min<Eigen::Index>(200, std::max<Eigen::Index>(1, N / 10));
  const Eigen::MatrixXd Yhat = simulate(model, U);
  double widest = 1.0;
  for (int o = 0; o < model.outputs; ++o) {
    // X: each estimated element's unit-gain response to its input (0 elsewhere).
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(N, n);
    std::vector<int> used;
    for (int i = 0; i < n; ++i) {
      const ElementEstimate& e = model.element(o, i);
      if (!e.estimated() || !std::isfinite(e.std_error.gain) || e.value.gain == 0.0) continue;
      IdentifiedModel unit = model;
      for (ElementEstimate& u : unit.elements) u.value.gain = 0.0;
      unit.element(o, i).value.gain = 1.0;
      X.col(i) = simulate(unit, U).col(o);
      used.push_back(i);
    }
    if (used.empty()) continue;
    Eigen::MatrixXd Xu(N, static_cast<Eigen::Index>(used.size()));
    for (std::size_t c = 0; c < used.size(); ++c) {
      Xu.col(static_cast<Eigen::Index>(c)) = X.col(used[c]);
    }
    Eigen::VectorXd e = Y.col(o) - Yhat.col(o);
    for (Eigen::Index k = 0; k < N; ++k) {
      if (k >= layout.weight.size() || layout.weight(k) == 0.0 || !std::isfinite(e(k))) e(k) = 0.0;
      if (k < layout.weight.size() && layout.weight(k) == 0.0) Xu.row(k).setZero();
    }
    const Eigen::Index M = layout.scored();
    const Eigen::MatrixXd XtX = Xu.transpose() * Xu;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(XtX);
    if (ldlt.info() != Eigen::Success || M <= Xu.cols()) continue;
    const Eigen::MatrixXd inv = ldlt.solve(Eigen::MatrixXd::Identity(Xu.cols(), Xu.cols()));
    const Eigen::MatrixXd g = Xu.array().colwise() * e.array();  // rows: x_k e_k
    Eigen::MatrixXd omega = g.transpose() * g;
    for (Eigen::Index l = 1; l <= L && l < N; ++l) {
      const double w = 1.0 - static_cast<double>(l) / static_cast<double>(L + 1);
      const Eigen::MatrixXd gamma = g.bottomRows(N - l).transpose() * g.topRows(N - l);
      omega += w * (gamma + gamma.transpose());
    }
    const Eigen::MatrixXd hac = inv * omega * inv;
    const double s2 = e.squaredNorm() / static_cast<double>(M - Xu.cols());
    Eigen::VectorXd factor = Eigen::VectorXd::Ones(n);
    for (std::size_t c = 0; c < used.size(); ++c) {
      const auto cc = static_cast<Eigen::Index>(c);
      const double white = s2 * inv(cc, cc);
      if (white > 0.0 && hac(cc, cc) > white) factor(used[c]) = std::sqrt(hac(cc, cc) / white);
    }
    for (int i = 0; i < n; ++i) {
      ElementEstimate& el = model.element(o, i);
      el.std_error.gain *= factor(i);
      el.covariance.row(kGain) *= factor(i);
      el.covariance.col(kGain) *= factor(i);
      widest = std::max(widest, factor(i));
    }
    auto& cov = model.gain_covariance[static_cast<std::size_t>(o)];
    cov = factor.asDiagonal() * cov * factor.asDiagonal();
  }
  if (result.gain_uncertainty) {
    result.gain_uncertainty = gain_uncertainty(model.static_gain(), model.gain_covariance);
  }
  return widest;
}

ClosedLoopIdentification identify_closed_loop(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                                              const Eigen::MatrixXd& Y, double T_min,
                                              const SampleLayout& layout,
                                              const IdentifyOptions& options, int stage1_lags) {
  ClosedLoopIdentification out;
  out.stage1 = project_on_reference(U, R, stage1_lags);
  out.two_stage = identify(out.stage1.u_hat, Y, T_min, layout, options);
  out.direct = identify(U, Y, T_min, layout, options);
  out.se_widening_two_stage =
      widen_for_coloured_residuals(out.two_stage, out.stage1.u_hat, Y, layout);
  out.se_widening_direct = widen_for_coloured_residuals(out.direct, U, Y, layout);
  out.feedback_bias = gain_disagreements(out.two_stage.model, out.direct.model);
  return out;
}

}  // namespace excite::host
