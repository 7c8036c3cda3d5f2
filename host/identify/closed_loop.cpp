// SPDX-License-Identifier: MIT
#include "host/identify/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/identify/two_stage_uncertainty.hpp"

namespace excite::host {

int default_stage1_lags(Eigen::Index rows, Eigen::Index channels) {
  return static_cast<int>(std::clamp<Eigen::Index>(rows / (8 * channels), 20, 200));
}

int default_instrument_lags(Eigen::Index rows, Eigen::Index channels) {
  return static_cast<int>(std::clamp<Eigen::Index>(rows / (32 * channels), 20, 200));
}

ReferenceProjection::ReferenceProjection(const Eigen::MatrixXd& R, int lags, double pole) {
  const Eigen::Index N = R.rows();
  const Eigen::Index m = R.cols();
  if (N == 0 || m == 0) {
    throw std::invalid_argument("r rows x channels = " + std::to_string(N) + "x" +
                                std::to_string(m) + ", expected at least one row and channel");
  }
  if (!R.allFinite()) throw std::invalid_argument("r = (not finite), expected finite values");
  if (R.cwiseAbs().maxCoeff() == 0.0) {
    throw std::invalid_argument(
        "r = 0 throughout, expected a test signal (the two-stage "
        "method needs r to explain u)");
  }
  if (!(pole >= 0.0 && pole < 1.0)) {
    throw std::invalid_argument("stage-1 pole = " + std::to_string(pole) +
                                ", expected 0 <= pole < 1");
  }
  if (lags == 0) lags = default_stage1_lags(N, m);
  const Eigen::Index P = static_cast<Eigen::Index>(lags) * m;
  if (lags < 1 || 2 * P >= N) {
    throw std::invalid_argument("stage-1 lags = " + std::to_string(lags) + " x " +
                                std::to_string(m) + " r channels, expected fewer than " +
                                std::to_string(N / 2) + " parameters for " + std::to_string(N) +
                                " rows");
  }
  Eigen::MatrixXd phi(N, P);
  const double a = pole, gain = std::sqrt(1.0 - a * a);
  for (Eigen::Index c = 0; c < m; ++c) {
    double state = 0.0;  // x₀ = √(1 − a²)/(1 − a q⁻¹) r_c
    for (Eigen::Index k = 0; k < N; ++k) {
      state = a * state + gain * R(k, c);
      phi(k, c) = state;
    }
    // x_l(k) = a·x_l(k−1) + x_{l−1}(k−1) − a·x_{l−1}(k): (1 − a q⁻¹) x_l = (q⁻¹ − a) x_{l−1}
    for (int l = 1; l < lags; ++l) {
      const Eigen::Index to = l * m + c, from = (l - 1) * m + c;
      phi(0, to) = -a * phi(0, from);
      for (Eigen::Index k = 1; k < N; ++k) {
        phi(k, to) = a * phi(k - 1, to) + phi(k - 1, from) - a * phi(k, from);
      }
    }
  }
  lags_ = lags;
  pole_ = pole;
  qr_.compute(phi);
}

// P_Φ X = Q₁Q₁ᵀX, Q₁ the first rank() Householder vectors. Solving R₁b = Q₁ᵀX and forming Φb
// loses the projection when Φ is nearly rank-deficient — a multisine r of few lines spans far
// fewer dimensions than its lags: alatiqi4x4 msGlmSim under its DMC, 508 columns of numerical
// rank ≈ 190, gave u2 a fit of −29 % that way (no projection fits worse than 0), 17 % this way.
Eigen::MatrixXd ReferenceProjection::operator()(const Eigen::MatrixXd& X) const {
  Eigen::MatrixXd coordinates = qr_.householderQ().transpose() * X;
  coordinates.bottomRows(X.rows() - qr_.rank()).setZero();
  return qr_.householderQ() * coordinates;
}

namespace {

// The memory of L Laguerre functions of pole a: the span of their impulse responses,
// L·(1 + a)/(1 − a) samples (a = 0: L lags).
double laguerre_memory(int functions, double pole) {
  return functions * (1.0 + pole) / (1.0 - pole);
}

void require_rows_of_u(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R) {
  if (R.rows() != U.rows() || U.cols() == 0) {
    throw std::invalid_argument("r rows x channels = " + std::to_string(R.rows()) + "x" +
                                std::to_string(R.cols()) + ", expected " +
                                std::to_string(U.rows()) + " rows (as u) and at least one channel");
  }
}

// Stage 1's projection for U: `pole` negative is chosen (choose_stage1_pole).
ReferenceProjection stage1_projection(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags,
                                      double pole) {
  require_rows_of_u(U, R);
  return ReferenceProjection(R, lags, pole < 0.0 ? choose_stage1_pole(U, R, lags) : pole);
}

}  // namespace

double choose_stage1_pole(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags) {
  constexpr double kPoles[] = {0.0, 0.5, 0.7, 0.8, 0.87, 0.92, 0.95, 0.97, 0.98};
  require_rows_of_u(U, R);
  if (lags == 0) lags = default_stage1_lags(R.rows(), R.cols());
  const int few = std::min(kStage1PoleFunctions, lags);
  Eigen::VectorXd spread(U.cols());
  for (Eigen::Index j = 0; j < U.cols(); ++j)
    spread(j) = std::max((U.col(j).array() - U.col(j).mean()).matrix().squaredNorm(), 1e-300);
  double scale = 0.0, least = std::numeric_limits<double>::infinity();
  for (const double a : kPoles) {
    const Eigen::MatrixXd left = U - ReferenceProjection(R, few, a)(U);
    const double unexplained = left.colwise().squaredNorm().cwiseQuotient(spread.transpose()).sum();
    if (unexplained < least) {
      least = unexplained;
      scale = a;
    }
  }
  // The pole whose `lags` functions reach kStage1MemoryFactor times the memory of the best
  // few: L·(1 + a)/(1 − a) = M, a = (M/L − 1)/(M/L + 1), within [0, the best few's pole].
  const double ratio = kStage1MemoryFactor * laguerre_memory(few, scale) / lags;
  return std::clamp((ratio - 1.0) / (ratio + 1.0), 0.0, scale);
}

Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R, int lags,
                               double pole) {
  return project_on_reference(U, stage1_projection(U, R, lags, pole));
}

Stage1Fit project_on_reference(const Eigen::MatrixXd& U, const ReferenceProjection& P) {
  if (U.rows() != P.rows() || U.cols() == 0) {
    throw std::invalid_argument("u rows x inputs = " + std::to_string(U.rows()) + "x" +
                                std::to_string(U.cols()) + ", expected " +
                                std::to_string(P.rows()) + " rows (as r) and at least one input");
  }
  if (!U.allFinite()) throw std::invalid_argument("u = (not finite), expected finite values");
  Stage1Fit fit;
  fit.lags = P.lags();
  fit.pole = P.pole();
  fit.u_hat = P(U);
  fit.fit_percent.resize(U.cols());
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    const double spread = (U.col(j).array() - U.col(j).mean()).matrix().norm();
    fit.fit_percent(j) =
        spread > 0.0 ? 100.0 * (1.0 - (U.col(j) - fit.u_hat.col(j)).norm() / spread) : std::nan("");
  }
  return fit;
}

namespace {

// The SE that e's reported 95 % interval (gain_interval_95) gives on the side facing `other`:
// its half-width there over 1.96. K ± 1.96·SE's own SE where no projection widens that side.
double se_towards(const ElementEstimate& e, double other) {
  const GainBounds b = gain_interval_95(e);
  const double K = e.value.gain;
  return (other >= K ? b.upper - K : K - b.lower) / 1.96;
}

}  // namespace

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
      const double ka = ea.value.static_gain(), kb = eb.value.static_gain();
      if (!std::isfinite(ka) || !std::isfinite(kb)) continue;  // an integrator's
      const double sa = se_towards(ea, kb), sb = se_towards(eb, ka);
      if (!std::isfinite(sa) || !std::isfinite(sb)) continue;
      const double sigma = std::sqrt(sa * sa + sb * sb);
      if (std::abs(ka - kb) > k * sigma) out.push_back({o, i, ka, kb, sigma});
    }
  }
  return out;
}

Eigen::MatrixXd instrument_inputs(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                                  int stage1_lags) {
  const int lags =
      std::min(default_instrument_lags(R.rows(), R.cols()),
               stage1_lags > 0 ? stage1_lags : default_stage1_lags(R.rows(), R.cols()));
  return ReferenceProjection(R, lags, choose_stage1_pole(U, R, lags))(U);
}

std::vector<Structure> lags_for_rates_not_told_from_zero(const IdentifiedModel& model) {
  std::vector<Structure> structures;
  bool any = false;
  for (const ElementEstimate& e : model.elements) {
    Structure s = e.estimated() ? e.value.structure : Structure::two_poles;
    if (s == Structure::integrator && !(std::abs(e.value.gain) > 1.96 * e.std_error.gain)) {
      s = Structure::first_order;
      any = true;
    }
    structures.push_back(s);
  }
  if (!any) structures.clear();
  return structures;
}

TwoStageFit identify_two_stage(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                               const Eigen::MatrixXd& Y, double T_min, const SampleLayout& layout,
                               const IdentifyOptions& options, int stage1_lags,
                               const NoiseModelOptions& noise, double stage1_pole) {
  TwoStageFit out;
  const ReferenceProjection P = stage1_projection(U, R, stage1_lags, stage1_pole);
  out.stage1 = project_on_reference(U, P);
  const Eigen::MatrixXd u_iv = instrument_inputs(U, R, P.lags());
  const auto stage2 = [&](const IdentifyOptions& o) {
    out.fit = identify_with_noise_model(out.stage1.u_hat, Y, T_min, layout, o, noise);
    IdentifiedModel& model = out.fit.result.model;
    out.stage1_se_factor.resize(model.outputs, model.inputs);
    out.iv_gain_step.resize(model.outputs, model.inputs);
    for (int j = 0; j < model.outputs; ++j) {
      const InstrumentStep step =
          instrument_step_in_row(model, j, U, u_iv, Y.col(j), layout, noise.max_order);
      out.stage1_se_factor.row(j) = step.se_factor.transpose();
      out.iv_gain_step.row(j) = step.gain_step.transpose();
      out.fit.result.fits[static_cast<std::size_t>(j)].noise_level_dof = step.noise_level_dof;
    }
  };
  IdentifyOptions on_u_hat = options;
  on_u_hat.projection_scope = ProjectionScope::instrument_step_follows;  // its bias: the step
  stage2(on_u_hat);
  if (!options.structure && options.structures.empty()) {
    IdentifyOptions lags = on_u_hat;
    lags.structures = lags_for_rates_not_told_from_zero(out.fit.result.model);
    if (!lags.structures.empty()) stage2(lags);
  }
  analyse_identified_gain(out.fit.result);
  return out;
}

ClosedLoopIdentification identify_closed_loop(const Eigen::MatrixXd& U, const Eigen::MatrixXd& R,
                                              const Eigen::MatrixXd& Y, double T_min,
                                              const SampleLayout& layout,
                                              const IdentifyOptions& options, int stage1_lags,
                                              const NoiseModelOptions& noise, double stage1_pole) {
  ClosedLoopIdentification out;
  TwoStageFit two_stage =
      identify_two_stage(U, R, Y, T_min, layout, options, stage1_lags, noise, stage1_pole);
  NoiseModelFit direct = identify_with_noise_model(U, Y, T_min, layout, options, noise);
  out.stage1 = std::move(two_stage.stage1);
  out.stage1_se_factor = std::move(two_stage.stage1_se_factor);
  out.iv_gain_step = std::move(two_stage.iv_gain_step);
  out.two_stage = std::move(two_stage.fit.result);
  out.noise_two_stage = std::move(two_stage.fit.noise);
  out.se_widening_two_stage = two_stage.fit.se_widening;
  out.direct = std::move(direct.result);
  out.noise_direct = std::move(direct.noise);
  out.se_widening_direct = direct.se_widening;
  out.feedback_bias = gain_disagreements(out.two_stage.model, out.direct.model);
  return out;
}

}  // namespace excite::host
