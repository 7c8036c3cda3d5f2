// SPDX-License-Identifier: MIT
#include "host/identify/two_stage_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <Eigen/SVD>

#include "host/identify/gain_sensitivity.hpp"

namespace excite::host {
namespace {

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

// ∂ŷ_o/∂θ on Uf: the gains' sensitivities (their inputs in `used`), then the other parameters'.
Eigen::MatrixXd row_sensitivities(const IdentifiedModel& model, int output,
                                  const Eigen::MatrixXd& Uf, const std::vector<Segment>& segments,
                                  std::vector<int>& used) {
  RowGainSensitivity s = row_gain_sensitivity(model, output, Uf, segments);
  used = s.used;
  const Eigen::MatrixXd more = other_parameter_sensitivities(model, output, Uf, segments);
  Eigen::MatrixXd J(s.X.rows(), s.X.cols() + more.cols());
  J << s.X, more;
  return J;
}

// Row `output` linearised about stage 2's estimate on the data prefiltered by `noise`; rows
// not scored (or not finite) are zero in all three.
struct RowLinearisation {
  std::vector<int> used;  // the inputs of Z's first columns, the gains
  Eigen::MatrixXd Z;      // the sensitivities on u_iv: the instruments
  Eigen::MatrixXd J_u;    // the same on the applied u
  Eigen::VectorXd e_u;    // the prediction error on the applied u
};

RowLinearisation linearise_row(const IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                               const Eigen::MatrixXd& u_iv, const Eigen::VectorXd& y,
                               const ArNoiseModel& noise, const SampleLayout& layout) {
  const std::vector<Segment>& segments = layout.segments;
  const Eigen::MatrixXd Uf = prefilter(u_iv, noise, layout);
  const Eigen::MatrixXd Uuf = prefilter(U, noise, layout);
  RowLinearisation row;
  row.Z = row_sensitivities(model, output, Uf, segments, row.used);
  std::vector<int> same;
  row.J_u = row_sensitivities(model, output, Uuf, segments, same);
  row.e_u = prefilter(y, noise, layout) - simulate_row(model, output, Uuf, segments);
  const SampleLayout scored = prefiltered_layout(layout, noise.order());
  for (Eigen::Index k = 0; k < row.e_u.size(); ++k) {
    if (scored.weight(k) == 0.0 || !std::isfinite(row.e_u(k)) || !row.Z.row(k).allFinite() ||
        !row.J_u.row(k).allFinite()) {
      row.e_u(k) = 0.0;
      row.Z.row(k).setZero();
      row.J_u.row(k).setZero();
    }
  }
  return row;
}

// Of the scaled ZᵀJ_u, the largest condition number a step is taken with. Measured on
// alatiqi4x4 under its DMC (100 seeds): determined rows 10³–10⁵, the others 10⁷–10¹².
constexpr double kMaxCondition = 1e6;

// The columns of `A` (the scaled ZᵀJ_u, its first `gains` columns the gains) the step solves
// for: while A is worse conditioned than kMaxCondition, the other parameter that weighs most in
// its weakest direction is held at stage 2's value (two lags of nearly one value, whose split
// the instruments do not tell). Empty when the gains themselves are not determined.
std::vector<Eigen::Index> determined_columns(const Eigen::MatrixXd& A, Eigen::Index gains) {
  std::vector<Eigen::Index> keep(static_cast<std::size_t>(A.cols()));
  std::iota(keep.begin(), keep.end(), Eigen::Index{0});
  for (;;) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A(keep, keep), Eigen::ComputeFullV);
    const Eigen::VectorXd& sv = svd.singularValues();
    const Eigen::Index n = sv.size();
    if (sv(n - 1) * kMaxCondition > sv(0)) return keep;
    if (n == gains) return {};
    Eigen::Index held = 0;  // among the other parameters
    svd.matrixV().col(n - 1).tail(n - gains).cwiseAbs().maxCoeff(&held);
    keep.erase(keep.begin() + gains + held);
  }
}

}  // namespace

InstrumentStep instrument_step_in_row(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                      const Eigen::MatrixXd& u_iv, const Eigen::VectorXd& y,
                                      const SampleLayout& layout, int max_noise_order) {
  // The step's prefilter: the noise model of the error on the applied u, v's at the truth
  // (stage 2's describes v + G(u − û)).
  const Eigen::VectorXd error = y - simulate_row(model, output, U, layout.segments);
  const ArNoiseModel applied = fit_ar_noise(error, layout, max_noise_order);
  InstrumentStep out{Eigen::VectorXd::Zero(model.inputs), Eigen::VectorXd::Ones(model.inputs),
                     low_frequency_level_dof(error, applied, layout)};
  const RowLinearisation row = linearise_row(model, output, U, u_iv, y, applied, layout);
  if (row.used.empty()) return out;
  // Each parameter in units of its own sensitivity on u: a gain's and a time constant's differ
  // by up to seven orders of magnitude, and unscaled, ZᵀJ_u looked singular where it was not.
  Eigen::VectorXd scale = row.J_u.colwise().norm().transpose();
  scale = scale.unaryExpr([](double n) { return n > 0.0 ? 1.0 / n : 1.0; });
  const auto gains = static_cast<Eigen::Index>(row.used.size());
  const std::vector<Eigen::Index> keep = determined_columns(
      scale.asDiagonal() * (row.Z.transpose() * row.J_u) * scale.asDiagonal(), gains);
  if (keep.empty()) return out;
  const Eigen::MatrixXd Z = row.Z(Eigen::all, keep) * scale(keep).asDiagonal();
  const Eigen::MatrixXd J_u = row.J_u(Eigen::all, keep) * scale(keep).asDiagonal();
  const Eigen::MatrixXd A_inv = (Z.transpose() * J_u).partialPivLu().inverse();
  const Eigen::VectorXd step =
      scale.head(gains).asDiagonal() * (A_inv * (Z.transpose() * row.e_u)).head(gains);
  const Eigen::MatrixXd score = Z.array().colwise() * row.e_u.array();  // z_k ε_u,k
  // Few lags where the prefilter whitened ε_u; without a noise model (output error) ε_u is
  // the disturbance itself, and its colour needs the long window.
  const Eigen::Index L = max_noise_order > 0 ? whitened_long_run_lags(row.e_u.size())
                                             : default_long_run_lags(row.e_u.size());
  const Eigen::VectorXd iv = (A_inv * long_run_covariance(score, L) * A_inv.transpose())
                                 .diagonal()
                                 .head(gains)
                                 .cwiseProduct(scale.head(gains).cwiseAbs2());
  for (std::size_t c = 0; c < row.used.size(); ++c) {
    const auto k = static_cast<Eigen::Index>(c);
    const int i = row.used[c];
    ElementEstimate& el = model.element(output, i);
    const double own = el.std_error.gain;
    // A gain whose stage-2 SE is infinite keeps it: the step's SE is written as a factor on
    // stage 2's, which cannot carry it (inf·0), and its projection is its interval.
    if (!std::isfinite(step(k)) || !(iv(k) > 0.0) || !std::isfinite(iv(k)) ||
        !(std::isfinite(own) && own > 0.0))
      continue;
    out.gain_step(i) = step(k);
    out.se_factor(i) = std::sqrt(iv(k) + el.profile_variance) / own;
    el.value.gain += step(k);
    if (el.projected_gain) {
      el.projected_gain->bounds.lower += step(k);
      el.projected_gain->bounds.upper += step(k);
    }
  }
  scale_row_gain_ses(model, output, out.se_factor);
  return out;
}

}  // namespace excite::host
