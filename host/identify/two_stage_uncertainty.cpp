// SPDX-License-Identifier: MIT
#include "host/identify/two_stage_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host/identify/gain_sensitivity.hpp"

namespace excite::host {
namespace {

// X with each segment's rows in reverse order: the adjoint of a causal filter run per segment
// from rest is reversal, the filter, reversal.
Eigen::MatrixXd reversed_in_segments(const Eigen::MatrixXd& X,
                                     const std::vector<Segment>& segments) {
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (const Segment& s : segments) {
    const Eigen::Index n = s.end - s.begin;
    out.middleRows(s.begin, n) = X.middleRows(s.begin, n).colwise().reverse();
  }
  return out;
}

// Each column of X through element (output, input), its gain included.
Eigen::MatrixXd through_element(const IdentifiedModel& model, int output, int input,
                                const Eigen::MatrixXd& X, const std::vector<Segment>& segments) {
  const sim::DiscreteTerm g = discretise(model.element(output, input).value, model.sample_time_min);
  Eigen::MatrixXd out(X.rows(), X.cols());
  for (Eigen::Index c = 0; c < X.cols(); ++c) out.col(c) = element_output(g, X.col(c), segments);
  return out;
}

// ∂ŷ_o/∂θ on Uf for the row's estimated elements' free parameters other than K that are
// neither on a bound nor without an SE (central differences, step 1e-4·max(|θ|, 1), kept in
// the parameter's range: T's ≥ 0, Tz either sign, kMinDamping ≤ ζ ≤ 1): the gains'
// covariance is the block of the whole row's.
Eigen::MatrixXd other_parameter_sensitivities(const IdentifiedModel& model, int output,
                                              const Eigen::MatrixXd& Uf,
                                              const std::vector<Segment>& segments) {
  std::vector<Eigen::VectorXd> columns;
  for (int i = 0; i < model.inputs; ++i) {
    const ElementEstimate& el = model.element(output, i);
    if (!el.estimated()) continue;
    for (const int q : free_parameters(el.value.structure)) {
      if (q == kGain || el.at_bound[static_cast<std::size_t>(q)] != Bound::none ||
          !std::isfinite(el.std_error[q]))
        continue;
      const double inf = std::numeric_limits<double>::infinity();
      const double low = q == kZero ? -inf : q == kDamping ? kMinDamping : 0.0;
      const double high = q == kDamping ? 1.0 : inf;
      const double h = 1e-4 * std::max(std::abs(el.value[q]), 1.0);
      ElementModel up = el.value, down = el.value;
      up[q] = std::min(el.value[q] + h, high);
      down[q] = std::max(el.value[q] - h, low);
      if (!(up[q] > down[q])) continue;
      columns.push_back(
          (element_output(discretise(up, model.sample_time_min), Uf.col(i), segments) -
           element_output(discretise(down, model.sample_time_min), Uf.col(i), segments)) /
          (up[q] - down[q]));
    }
  }
  Eigen::MatrixXd out(Uf.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c)
    out.col(static_cast<Eigen::Index>(c)) = columns[c];
  return out;
}

}  // namespace

Eigen::VectorXd count_stage1_in_row(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                    const Eigen::MatrixXd& u_hat, const Eigen::VectorXd& y,
                                    const ArNoiseModel& noise, const SampleLayout& layout,
                                    const ReferenceProjection& P) {
  Eigen::VectorXd factor = Eigen::VectorXd::Ones(model.inputs);
  const std::vector<Segment>& segments = layout.segments;
  const SampleLayout scored = prefiltered_layout(layout, noise.order());
  const Eigen::MatrixXd Uf = prefilter(u_hat, noise, layout);
  RowGainSensitivity s = row_gain_sensitivity(model, output, Uf, segments);
  if (s.used.empty()) return factor;
  // J: the gains' sensitivities first, then the row's other parameters'.
  const Eigen::MatrixXd more = other_parameter_sensitivities(model, output, Uf, segments);
  Eigen::MatrixXd J(s.X.rows(), s.X.cols() + more.cols());
  J << s.X, more;
  // ε: stage 2's prediction error, A_o(v + G(u − û)) at the truth; ε_u: the estimate's on the
  // applied u, the disturbance's part of it.
  const Eigen::VectorXd yf = prefilter(y, noise, layout);
  Eigen::VectorXd e = yf - simulate_row(model, output, Uf, segments);
  Eigen::VectorXd e_u = yf - simulate_row(model, output, prefilter(U, noise, layout), segments);
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    if (scored.weight(k) == 0.0 || !std::isfinite(e(k)) || !std::isfinite(e_u(k))) {
      e(k) = 0.0;
      e_u(k) = 0.0;
      J.row(k).setZero();
    }
  }
  const Eigen::Index q = J.cols();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(J.transpose() * J);
  if (ldlt.info() != Eigen::Success) return factor;
  const Eigen::MatrixXd inv = ldlt.solve(Eigen::MatrixXd::Identity(q, q));
  // Aᵀ J, in each segment's reversed time (reversal, A, then each element, reversal).
  const Eigen::MatrixXd back = prefilter(reversed_in_segments(J, segments), noise, layout);
  Eigen::MatrixXd influence = J.array().colwise() * e_u.array();  // j_k ε_u,k, then + h_k w_k
  for (int i = 0; i < model.inputs; ++i) {
    if (!model.element(output, i).estimated()) continue;
    const Eigen::MatrixXd adjoint =
        reversed_in_segments(through_element(model, output, i, back, segments), segments);
    const Eigen::MatrixXd h = adjoint - P(adjoint);
    const Eigen::VectorXd w = U.col(i) - u_hat.col(i);
    influence += (h.array().colwise() * w.array()).matrix();
  }
  const Eigen::Index L = default_long_run_lags(e.size());
  const Eigen::MatrixXd own = J.array().colwise() * e.array();  // stage 2's: j_k ε_k
  const Eigen::VectorXd stage2 = (inv * long_run_covariance(own, L) * inv).diagonal();
  const Eigen::VectorXd both = (inv * long_run_covariance(influence, L) * inv).diagonal();
  for (std::size_t c = 0; c < s.used.size(); ++c) {
    const auto k = static_cast<Eigen::Index>(c);
    if (stage2(k) > 0.0 && std::isfinite(both(k)) && both(k) > stage2(k))
      factor(s.used[c]) = std::sqrt(both(k) / stage2(k));
  }
  widen_row_gains(model, output, factor);
  return factor;
}

}  // namespace excite::host
