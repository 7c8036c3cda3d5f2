// SPDX-License-Identifier: MIT
#include "host/export/step_response.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "host/identify/miso_fit.hpp"

namespace excite::host {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr double kEqualRoots = 1e-6;  // relative difference of T_p1, T_p2 taken as equal

// s(t) by the exact ZOH discretisation at sample time t: a step is held constant, so the
// discretised element's second sample is the continuous response at t (any structure).
double step_response_by_zoh(const ElementModel& p, double t_min) {
  const sim::DiscreteTerm d = discretise(p, t_min);
  const std::array<double, 2> u{1.0, 1.0};
  std::array<double, 2> y{};
  simulate(d, u, y);
  return y[1];
}

// Where a projection widens the gain's reported interval beyond K ± 1.96·SE (model.hpp,
// gain_interval_95), the gain's row and column of C scaled so that its ±1.96σ reaches the
// interval's farther end: the band's final value then holds what the report states of K,
// and the gain keeps its correlations with the element's dynamics.
void widen_gain_to_reported_interval(const ElementEstimate& estimate,
                                     ElementEstimate::Covariance& C) {
  const double variance = C(kGain, kGain);
  if (!estimate.projected_gain || !(variance > 0.0) || !std::isfinite(variance)) return;
  const GainBounds b = gain_interval_95(estimate);
  const double K = estimate.value.gain;
  const double factor = std::max(b.upper - K, K - b.lower) / (1.96 * std::sqrt(variance));
  if (!(factor > 1.0) || !std::isfinite(factor)) return;
  C.row(kGain) *= factor;
  C.col(kGain) *= factor;
}

}  // namespace

double step_response(const ElementModel& p, double t_min) {
  const double tau = t_min - p.delay_min;
  if (!(tau > 0.0)) return 0.0;
  if (p.structure != Structure::two_poles && p.structure != Structure::first_order) {
    return step_response_by_zoh(p, t_min);
  }
  const double a = std::max(p.tau1_min, p.tau2_min);
  const double b = std::min(p.tau1_min, p.tau2_min);
  if (a == 0.0) return p.gain;
  if (b == 0.0) return p.gain * -std::expm1(-tau / a);
  if (a - b <= kEqualRoots * a) {
    const double T = 0.5 * (a + b);
    return p.gain * (1.0 - (1.0 + tau / T) * std::exp(-tau / T));
  }
  return p.gain * (1.0 - (a * std::exp(-tau / a) - b * std::exp(-tau / b)) / (a - b));
}

Settling slowest_settling(const IdentifiedModel& model) {
  Settling s;
  for (int o = 0; o < model.outputs; ++o) {
    for (int i = 0; i < model.inputs; ++i) {
      const ElementEstimate& e = model.element(o, i);
      if (!e.estimated()) continue;
      const double samples = std::ceil(settling_time_min(e.value) / model.sample_time_min);
      if (s.output < 0 || samples > s.samples) s = {std::max(1.0, samples), o, i};
    }
  }
  return s;
}

int settling_samples(const IdentifiedModel& model) {
  const double samples = slowest_settling(model).samples;
  return std::isfinite(samples) && samples < kMaxSettlingSamples ? static_cast<int>(samples)
                                                                 : kMaxSettlingSamples;
}

StepBand step_band(const ElementEstimate& estimate, const std::vector<double>& times_min) {
  StepBand band;
  band.response.reserve(times_min.size());
  band.sigma.reserve(times_min.size());
  const ElementModel& p = estimate.value;
  const std::span<const int> free = free_parameters(p.structure);
  ElementEstimate::Covariance C = estimate.covariance;
  bool known = false;
  for (const int k : free) known |= !std::isnan(C(k, k));
  if (!known) {  // no covariance: the standard errors alone
    C.setConstant(std::numeric_limits<double>::quiet_NaN());
    for (const int k : free) C(k, k) = estimate.std_error[k] * estimate.std_error[k];
  }
  widen_gain_to_reported_interval(estimate, C);
  // Central-difference steps: relative to the parameter, at least 1e-6 of the time scale.
  const double time_scale =
      std::max({p.delay_min, p.tau1_min, p.tau2_min, std::abs(p.zero_min), p.natural_min, 1e-3});
  std::array<double, kParameters> h{};
  for (const int k : free) {
    const double v = p[k];
    const double typical = k == kGain ? 1e-12 : (k == kDamping ? 1.0 : time_scale);
    h[static_cast<std::size_t>(k)] = 1e-6 * std::max(std::abs(v), typical);
  }
  for (const double t : times_min) {
    band.response.push_back(step_response(p, t));
    Eigen::Matrix<double, kParameters, 1> g = Eigen::Matrix<double, kParameters, 1>::Zero();
    for (const int k : free) {
      const double hk = h[static_cast<std::size_t>(k)];
      const ParameterRange r = parameter_range(k, MisoBounds{kInf, kInf});
      ElementModel up = p, down = p;
      // A parameter on the edge of its range is differentiated one-sided.
      const bool up_only = p[k] - hk < r.lower;
      const bool down_only = p[k] + hk > r.upper;
      if (!down_only) up[k] = p[k] + hk;
      if (!up_only) down[k] = p[k] - hk;
      g(k) =
          (step_response(up, t) - step_response(down, t)) / (up_only || down_only ? hk : 2.0 * hk);
    }
    double variance = 0.0;
    for (const int a : free) {
      for (const int b : free) {
        const double c = C(a, b);
        if (std::isnan(c) || g(a) == 0.0 || g(b) == 0.0) continue;  // on a bound: exact
        variance += g(a) * c * g(b);
      }
    }
    band.sigma.push_back(std::isnan(variance) ? std::numeric_limits<double>::infinity()
                                              : std::sqrt(std::max(variance, 0.0)));
  }
  return band;
}

}  // namespace excite::host
