// SPDX-License-Identifier: MIT
#include "host/identify/gain_sensitivity.hpp"

#include <algorithm>
#include <cmath>

namespace excite::host {
namespace {

// Element (output, input)'s response to U's column `input`, the element's own gain replaced
// by `gain`, each segment from rest.
Eigen::VectorXd element_response(const IdentifiedModel& model, int output, int input,
                                 const Eigen::MatrixXd& U, const std::vector<Segment>& segments,
                                 double gain) {
  ElementModel g = model.element(output, input).value;
  g.gain = gain;
  return element_output(discretise(g, model.sample_time_min), U.col(input), segments);
}

}  // namespace

Eigen::VectorXd element_output(const sim::DiscreteTerm& g, const Eigen::VectorXd& u,
                               const std::vector<Segment>& segments) {
  const auto N = static_cast<std::size_t>(u.size());
  Eigen::VectorXd y(u.size());
  simulate_segments(g, {u.data(), N}, {y.data(), N}, segments);
  return y;
}

Eigen::VectorXd simulate_row(const IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                             const std::vector<Segment>& segments) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(U.rows());
  for (int i = 0; i < model.inputs; ++i) {
    const ElementEstimate& e = model.element(output, i);
    if (e.estimated()) y += element_response(model, output, i, U, segments, e.value.gain);
  }
  return y;
}

RowGainSensitivity row_gain_sensitivity(const IdentifiedModel& model, int output,
                                        const Eigen::MatrixXd& U,
                                        const std::vector<Segment>& segments) {
  RowGainSensitivity s;
  for (int i = 0; i < model.inputs; ++i) {
    const ElementEstimate& e = model.element(output, i);
    if (e.estimated() && std::isfinite(e.std_error.gain) && e.value.gain != 0.0)
      s.used.push_back(i);
  }
  s.X.resize(U.rows(), static_cast<Eigen::Index>(s.used.size()));
  for (std::size_t c = 0; c < s.used.size(); ++c)
    s.X.col(static_cast<Eigen::Index>(c)) =
        element_response(model, output, s.used[c], U, segments, 1.0);
  return s;
}

void scale_row_gain_ses(IdentifiedModel& model, int output, const Eigen::VectorXd& factor) {
  for (int i = 0; i < model.inputs; ++i) {
    ElementEstimate& el = model.element(output, i);
    el.std_error.gain *= factor(i);
    el.covariance.row(kGain) *= factor(i);
    el.covariance.col(kGain) *= factor(i);
  }
  auto& cov = model.gain_covariance[static_cast<std::size_t>(output)];
  cov = factor.asDiagonal() * cov * factor.asDiagonal();
}

Eigen::MatrixXd long_run_covariance(const Eigen::MatrixXd& g, Eigen::Index max_lag) {
  const Eigen::Index N = g.rows();
  Eigen::MatrixXd omega = g.transpose() * g;
  for (Eigen::Index l = 1; l <= max_lag && l < N; ++l) {
    const double w = 1.0 - static_cast<double>(l) / static_cast<double>(max_lag + 1);
    const Eigen::MatrixXd gamma = g.bottomRows(N - l).transpose() * g.topRows(N - l);
    omega += w * (gamma + gamma.transpose());
  }
  return omega;
}

Eigen::Index default_long_run_lags(Eigen::Index rows) {
  return std::min<Eigen::Index>(200, std::max<Eigen::Index>(1, rows / 10));
}

Eigen::Index whitened_long_run_lags(Eigen::Index rows) {
  const double lags = 4.0 * std::pow(static_cast<double>(rows) / 100.0, 2.0 / 9.0);
  return std::max<Eigen::Index>(1, static_cast<Eigen::Index>(lags));
}

double widen_row_for_coloured_residual(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                       const Eigen::VectorXd& y, const SampleLayout& layout,
                                       int max_lag) {
  const Eigen::Index N = U.rows();
  const Eigen::Index L = max_lag > 0 ? max_lag : default_long_run_lags(N);
  RowGainSensitivity s = row_gain_sensitivity(model, output, U, layout.segments);
  if (s.used.empty()) return 1.0;
  Eigen::VectorXd e = y - simulate_row(model, output, U, layout.segments);
  for (Eigen::Index k = 0; k < N; ++k) {
    if (layout.weight(k) == 0.0 || !std::isfinite(e(k))) {
      e(k) = 0.0;
      s.X.row(k).setZero();
    }
  }
  const Eigen::Index M = layout.scored();
  const Eigen::Index P = s.X.cols();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.X.transpose() * s.X);
  if (ldlt.info() != Eigen::Success || M <= P) return 1.0;
  const Eigen::MatrixXd inv = ldlt.solve(Eigen::MatrixXd::Identity(P, P));
  const Eigen::MatrixXd g = s.X.array().colwise() * e.array();  // rows: x_k e_k
  const Eigen::MatrixXd hac = inv * long_run_covariance(g, L) * inv;
  const double s2 = e.squaredNorm() / static_cast<double>(M - P);
  Eigen::VectorXd factor = Eigen::VectorXd::Ones(model.inputs);
  for (Eigen::Index c = 0; c < P; ++c) {
    const double white = s2 * inv(c, c);
    if (white > 0.0 && hac(c, c) > white)
      factor(s.used[static_cast<std::size_t>(c)]) = std::sqrt(hac(c, c) / white);
  }
  scale_row_gain_ses(model, output, factor);
  return factor.maxCoeff();
}

}  // namespace excite::host
