// SPDX-License-Identifier: MIT
#include "host/identify/noise_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/identify/gain_sensitivity.hpp"
#include "host/identify/validate.hpp"
#include "host/process/parallel.hpp"

namespace excite::host {
namespace {

constexpr int kRowsPerParameter = 10;
constexpr double kExpansionTail = 1e-3;  // Σ |a_k| left out of an ARMA(1,1)'s expansion
constexpr int kExpansionMax = 100;

// A(q) of an ARMA(1,1): a_k = (zero − pole) zero^(k−1), k = 1 … K, K the first length whose
// tail |zero − pole| |zero|^K / (1 − |zero|) is below kExpansionTail.
Eigen::VectorXd arma_expansion(const ArmaPoleZero& m) {
  const double gap = std::abs(m.zero - m.pole);
  const double z = std::abs(m.zero);
  int K = 1;
  while (K < kExpansionMax && gap * std::pow(z, K) / (1.0 - z) > kExpansionTail) ++K;
  Eigen::VectorXd a(K);
  for (int k = 0; k < K; ++k) a(k) = (m.zero - m.pole) * std::pow(m.zero, k);
  return a;
}

// Each column of x through 1/(1 − zero·q⁻¹) in place, each segment from rest.
void through_zero(Eigen::Ref<Eigen::MatrixXd> x, double zero, const SampleLayout& layout) {
  const std::vector<std::array<double, kMaxPoles>> a(static_cast<std::size_t>(x.cols()),
                                                     {-zero, 0.0, 0.0});
  all_pole_filter_columns(a, x, layout.segments);
}

double sum_of_squares(const Eigen::VectorXd& x, const std::vector<Eigen::Index>& rows) {
  double sum = 0.0;
  for (const Eigen::Index k : rows) sum += x(k) * x(k);
  return sum;
}

// v with each segment's mean over its scored rows removed.
Eigen::VectorXd about_segment_means(const Eigen::VectorXd& v, const SampleLayout& layout) {
  Eigen::VectorXd x = v;
  for (const Segment& s : layout.segments) {
    const Eigen::Index len = s.end - s.begin;
    const double scored = layout.weight.segment(s.begin, len).sum();
    if (scored == 0.0) continue;
    const double mean = layout.weight.segment(s.begin, len).dot(v.segment(s.begin, len)) / scored;
    x.segment(s.begin, len).array() -= mean;
  }
  return x;
}

// Rows k whose `order` predecessors lie in k's segment and which, with them, are scored.
std::vector<Eigen::Index> regression_rows(const SampleLayout& layout, int order) {
  std::vector<Eigen::Index> rows;
  for (const Segment& s : layout.segments) {
    Eigen::Index run = 0;  // scored rows in a row, ending at k
    for (Eigen::Index k = s.begin; k < s.end; ++k) {
      run = layout.weight(k) != 0.0 ? run + 1 : 0;
      if (run > order) rows.push_back(k);
    }
  }
  return rows;
}

// x(k − j) in k's segment, 0 before it: column j − 1 for j = 1 … order.
Eigen::MatrixXd lagged_columns(const Eigen::VectorXd& x, int order, const SampleLayout& layout) {
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(x.size(), order);
  for (int j = 1; j <= order; ++j) add_lagged(Z.col(j - 1), x, j, 1.0, layout.segments);
  return Z;
}

IdentifiedModel row_model(const IdentifiedModel& model, int output) {
  IdentifiedModel row;
  row.inputs = model.inputs;
  row.outputs = 1;
  row.sample_time_min = model.sample_time_min;
  for (int i = 0; i < model.inputs; ++i) row.elements.push_back(model.element(output, i));
  row.gain_covariance = {model.gain_covariance[static_cast<std::size_t>(output)]};
  return row;
}

// The polish of one row on prefiltered data: from the row as it is, in its structures.
IdentifyOptions polish_options(const IdentifyOptions& options, const IdentifiedModel& model,
                               int output) {
  IdentifyOptions o = options;
  o.threads = 1;
  o.start = row_model(model, output);
  o.start_use = IdentifyOptions::StartUse::polish;
  o.structure.reset();  // the row's own structures below
  o.structures.clear();
  for (const ElementEstimate& e : o.start->elements)
    o.structures.push_back(e.estimated() ? e.value.structure : Structure::two_poles);
  return o;
}

// ∂ε/∂(noise parameters) of the output error v (noise_model.hpp): an AR's lags of v, an
// ARMA(1,1)'s two columns, each segment from rest. Signs are immaterial to the projection.
Eigen::MatrixXd noise_parameter_sensitivities(const Eigen::VectorXd& v, const ArNoiseModel& noise,
                                              const SampleLayout& layout) {
  if (!noise.arma) return lagged_columns(v, noise.order(), layout);
  const ArmaPoleZero& m = *noise.arma;
  Eigen::MatrixXd sources(v.size(), 2);
  sources << v, arma_prediction_error(v, m, layout);
  through_zero(sources, m.zero, layout);
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(v.size(), 2);
  for (int c = 0; c < 2; ++c) add_lagged(Z.col(c), sources.col(c), 1, 1.0, layout.segments);
  return Z;
}

// Widens row `output`'s gain SEs for the estimated noise parameters (noise_model.hpp): X_f
// the gain sensitivities on the prefiltered data, Z the prediction error's sensitivities to
// the noise parameters. Returns the largest factor.
double widen_for_noise_parameters(IdentifiedModel& model, int output, const Eigen::MatrixXd& Uf,
                                  const Eigen::VectorXd& v, const ArNoiseModel& noise,
                                  const SampleLayout& filtered) {
  RowGainSensitivity s = row_gain_sensitivity(model, output, Uf, filtered.segments);
  if (s.used.empty()) return 1.0;
  Eigen::MatrixXd Z = noise_parameter_sensitivities(v, noise, filtered);
  for (Eigen::Index k = 0; k < Z.rows(); ++k) {
    if (filtered.weight(k) != 0.0) continue;
    s.X.row(k).setZero();
    Z.row(k).setZero();
  }
  const Eigen::Index P = s.X.cols();
  const Eigen::MatrixXd XtX = s.X.transpose() * s.X;
  const Eigen::MatrixXd XtZ = s.X.transpose() * Z;
  const Eigen::LDLT<Eigen::MatrixXd> zz(Z.transpose() * Z);
  const Eigen::LDLT<Eigen::MatrixXd> xx(XtX);
  const Eigen::LDLT<Eigen::MatrixXd> schur(XtX - XtZ * zz.solve(XtZ.transpose()));
  if (zz.info() != Eigen::Success || xx.info() != Eigen::Success || schur.info() != Eigen::Success)
    return 1.0;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(P, P);
  const Eigen::VectorXd known = xx.solve(I).diagonal();
  const Eigen::VectorXd estimated = schur.solve(I).diagonal();
  Eigen::VectorXd factor = Eigen::VectorXd::Ones(model.inputs);
  for (Eigen::Index c = 0; c < P; ++c) {
    if (known(c) > 0.0 && estimated(c) > known(c))
      factor(s.used[static_cast<std::size_t>(c)]) = std::sqrt(estimated(c) / known(c));
  }
  scale_row_gain_ses(model, output, factor);
  return factor.maxCoeff();
}

struct RowData {
  const Eigen::MatrixXd& U;
  Eigen::VectorXd y;
  double T_min;
  const SampleLayout& layout;
  const IdentifyOptions& options;
  const NoiseModelOptions& noise;
};

// Row `output` of fit.result refitted with its noise model (noise_model.hpp); returns the
// largest SE widening.
double refit_row(const RowData& d, int output, NoiseModelFit& fit) {
  IdentifiedModel& model = fit.result.model;
  const std::vector<Segment>& segments = d.layout.segments;
  ArNoiseModel used;
  Eigen::MatrixXd Uf;
  for (int round = 0; round < d.noise.refits && d.noise.max_order > 0; ++round) {
    const Eigen::VectorXd v = d.y - simulate_row(model, output, d.U, segments);
    if (!v.allFinite()) break;
    ArNoiseModel next = fit_ar_noise(v, d.layout, d.noise.max_order);
    if (next.order() == 0) break;
    Eigen::MatrixXd next_Uf = prefilter(d.U, next, d.layout);
    const Eigen::VectorXd yf = prefilter(d.y, next, d.layout);
    const SampleLayout lf = prefiltered_layout(d.layout, next.order());
    IdentificationResult row;
    try {
      row = identify(next_Uf, yf, d.T_min, lf, polish_options(d.options, model, output));
    } catch (const std::invalid_argument&) {
      break;  // the prefilter left too few scored rows: the row stays as it is
    }
    Uf = std::move(next_Uf);
    for (int i = 0; i < model.inputs; ++i) model.element(output, i) = row.model.element(0, i);
    model.gain_covariance[static_cast<std::size_t>(output)] = row.model.gain_covariance[0];
    fit.result.fits[static_cast<std::size_t>(output)] = row.fits[0];
    used = std::move(next);
  }
  if (used.order() == 0) return widen_row_for_coloured_residual(model, output, d.U, d.y, d.layout);
  fit.noise[static_cast<std::size_t>(output)] = used;
  const Eigen::VectorXd y_hat = simulate_row(model, output, d.U, segments);
  OutputFit& f = fit.result.fits[static_cast<std::size_t>(output)];
  const Eigen::VectorXd y_scored = d.layout.scored_rows(d.y);
  const Eigen::VectorXd y_hat_scored = d.layout.scored_rows(y_hat);
  f.fit_percent = fit_percent(y_scored, y_hat_scored);
  f.residual_rms =
      (y_hat_scored - y_scored).norm() / std::sqrt(static_cast<double>(y_scored.size()));
  f.noise_level_dof = low_frequency_level_dof(d.y - y_hat, used, d.layout);
  const SampleLayout lf = prefiltered_layout(d.layout, used.order());
  const Eigen::VectorXd v = about_segment_means(d.y - y_hat, d.layout);
  const double by_parameters = widen_for_noise_parameters(model, output, Uf, v, used, lf);
  const double by_colour =
      widen_row_for_coloured_residual(model, output, Uf, prefilter(d.y, used, d.layout), lf);
  return std::max(by_parameters, by_colour);
}

}  // namespace

double low_frequency_level_dof(const Eigen::VectorXd& v, const ArNoiseModel& noise,
                               const SampleLayout& layout) {
  constexpr double kUntold = std::numeric_limits<double>::infinity();
  if (noise.order() == 0 || v.size() != layout.rows()) return kUntold;
  const SampleLayout filtered = prefiltered_layout(layout, noise.order());
  Eigen::MatrixXd Z =
      noise_parameter_sensitivities(about_segment_means(v, layout), noise, filtered);
  for (Eigen::Index k = 0; k < Z.rows(); ++k) {
    if (filtered.weight(k) == 0.0 || !Z.row(k).allFinite()) Z.row(k).setZero();
  }
  // ∂ ln L²/∂θ in Z's parameters: an AR's a_j all −2/A(1); an ARMA(1,1)'s columns are
  // −∂ε/∂pole and ∂ε/∂zero, and ln L² = 2 ln(1 − zero) − 2 ln(1 − pole).
  Eigen::VectorXd gradient(Z.cols());
  if (noise.arma) {
    gradient << -2.0 / (1.0 - noise.arma->pole), -2.0 / (1.0 - noise.arma->zero);
  } else {
    gradient.setConstant(-2.0 / (1.0 + noise.a.sum()));
  }
  const Eigen::LDLT<Eigen::MatrixXd> zz(Z.transpose() * Z);
  if (zz.info() != Eigen::Success) return kUntold;
  const double variance = noise.innovation_variance * gradient.dot(zz.solve(gradient));
  return variance > 0.0 && std::isfinite(variance) ? 2.0 / variance : kUntold;
}

ArNoiseModel fit_ar_noise(const Eigen::VectorXd& v, const SampleLayout& layout, int max_order) {
  if (v.size() != layout.rows() || max_order < 0) {
    throw std::invalid_argument("output error rows, AR order = " + std::to_string(v.size()) + ", " +
                                std::to_string(max_order) + ", expected " +
                                std::to_string(layout.rows()) + " rows and an order >= 0");
  }
  const Eigen::VectorXd x = about_segment_means(v, layout);
  std::vector<Eigen::Index> rows = regression_rows(layout, max_order);
  while (max_order > 0 &&
         static_cast<Eigen::Index>(rows.size()) < kRowsPerParameter * (max_order + 1)) {
    rows = regression_rows(layout, --max_order);
  }
  ArNoiseModel out;
  const auto M = static_cast<Eigen::Index>(rows.size());
  if (M == 0) return out;
  const double mean_square = sum_of_squares(x, rows) / static_cast<double>(M);
  out.innovation_variance = mean_square;
  if (max_order == 0 || mean_square == 0.0) return out;
  // [Φ x] with Φ's column j − 1 the lag j: one QR gives every order's residual sum of
  // squares (the last column of R from row n down) and its coefficients.
  const int n_max = max_order;
  Eigen::MatrixXd A(M, n_max + 1);
  for (Eigen::Index r = 0; r < M; ++r) {
    const Eigen::Index k = rows[static_cast<std::size_t>(r)];
    for (int j = 1; j <= n_max; ++j) A(r, j - 1) = x(k - j);
    A(r, n_max) = x(k);
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(n_max + 1).triangularView<Eigen::Upper>();
  const auto rss = [&](int n) { return R.col(n_max).segment(n, n_max + 1 - n).squaredNorm(); };
  const double m = static_cast<double>(M);
  const auto criterion = [m](double rss_p, int p) {  // BIC of p parameters over the M rows
    return m * std::log(std::max(rss_p, 1e-300) / m) + p * std::log(m);
  };
  const auto bic = [&](int n) { return criterion(rss(n), n); };
  int best = 0;
  for (int n = 1; n <= n_max; ++n) {
    if (bic(n) < bic(best)) best = n;
  }
  if (best == 0) return out;  // no ARMA on white noise: it would fit a pole and zero that cancel
  if (M >= kRowsPerParameter * 3) {
    const ArmaPoleZero arma = fit_arma11(x, rows, layout);
    const double rss_arma = sum_of_squares(arma_prediction_error(x, arma, layout), rows);
    if (criterion(rss_arma, 2) < bic(best)) {
      out.a = arma_expansion(arma);
      out.arma = arma;
      out.innovation_variance = rss_arma / m;
      return out;
    }
  }
  const Eigen::VectorXd c =
      R.topLeftCorner(best, best).triangularView<Eigen::Upper>().solve(R.col(n_max).head(best));
  out.a = -c;
  out.innovation_variance = rss(best) / static_cast<double>(M);
  return out;
}

std::string ArNoiseModel::name() const {
  if (arma) return "ARMA(1,1)";
  return order() == 0 ? "white" : "AR(" + std::to_string(order()) + ")";
}

Eigen::VectorXd arma_prediction_error(const Eigen::VectorXd& x, const ArmaPoleZero& arma,
                                      const SampleLayout& layout) {
  Eigen::VectorXd e = x;
  add_lagged(e, x, 1, -arma.pole, layout.segments);
  through_zero(e, arma.zero, layout);
  return e;
}

ArmaPoleZero fit_arma11(const Eigen::VectorXd& x, const std::vector<Eigen::Index>& rows,
                        const SampleLayout& layout) {
  const auto cost = [&](const ArmaPoleZero& m) {
    return sum_of_squares(arma_prediction_error(x, m, layout), rows);
  };
  ArmaPoleZero best;
  double least = cost(best);
  for (int p = 0; p <= 49; ++p) {
    for (int z = -9; z <= 9; ++z) {
      const ArmaPoleZero m{0.02 * p, 0.1 * z};
      const double c = cost(m);
      if (c < least) {
        least = c;
        best = m;
      }
    }
  }
  for (double step = 0.01; step > 1e-5; step /= 2.0) {
    for (bool moved = true; moved;) {
      moved = false;
      for (const auto& [dp, dz] : {std::pair{step, 0.0}, {-step, 0.0}, {0.0, step}, {0.0, -step}}) {
        const ArmaPoleZero m{std::clamp(best.pole + dp, 0.0, 0.999),
                             std::clamp(best.zero + dz, -0.9, 0.9)};
        const double c = cost(m);
        if (c < least) {
          least = c;
          best = m;
          moved = true;
        }
      }
    }
  }
  return best;
}

Eigen::MatrixXd prefilter(const Eigen::MatrixXd& X, const ArNoiseModel& noise,
                          const SampleLayout& layout) {
  Eigen::MatrixXd out = X;
  for (Eigen::Index c = 0; c < X.cols(); ++c) {
    const Eigen::VectorXd x = X.col(c);
    for (int j = 1; j <= noise.order(); ++j)
      add_lagged(out.col(c), x, j, noise.a(j - 1), layout.segments);
  }
  return out;
}

SampleLayout prefiltered_layout(const SampleLayout& layout, int order) {
  SampleLayout out = layout;
  for (const Segment& s : layout.segments) {
    Eigen::Index last_unscored = s.begin - 1;
    for (Eigen::Index k = s.begin; k < s.end; ++k) {
      if (layout.weight(k) == 0.0) last_unscored = k;
      if (last_unscored >= s.begin && k - last_unscored <= order) out.weight(k) = 0.0;
    }
  }
  return out;
}

NoiseModelFit identify_with_noise_model(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y,
                                        double T_min, const SampleLayout& layout,
                                        const IdentifyOptions& options,
                                        const NoiseModelOptions& noise) {
  NoiseModelFit fit;
  fit.result = identify(U, Y, T_min, layout, options);
  const int p = fit.result.model.outputs;
  fit.noise.assign(static_cast<std::size_t>(p), ArNoiseModel{});
  std::vector<double> widening(static_cast<std::size_t>(p), 1.0);
  // Rows on min(threads, p) threads; each writes only its own row, noise model and widening.
  parallel_for(p, options.threads, [&](int o) {
    const RowData d{U, Y.col(o), T_min, layout, options, noise};
    widening[static_cast<std::size_t>(o)] = refit_row(d, o, fit);
  });
  fit.se_widening = *std::max_element(widening.begin(), widening.end());
  analyse_identified_gain(fit.result);
  return fit;
}

}  // namespace excite::host
