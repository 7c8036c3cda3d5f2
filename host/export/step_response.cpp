// SPDX-License-Identifier: MIT
#include "host/export/step_response.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace excite::host {
namespace {

constexpr double kEqualRoots = 1e-6;  // relative difference of T_p1, T_p2 taken as equal

double parameter(const TwoPoleDelay& p, int k) {
  switch (k) {
    case kGain:
      return p.gain;
    case kDelay:
      return p.delay_min;
    case kTp1:
      return p.tau1_min;
    default:
      return p.tau2_min;
  }
}

void set_parameter(TwoPoleDelay& p, int k, double v) {
  switch (k) {
    case kGain:
      p.gain = v;
      break;
    case kDelay:
      p.delay_min = v;
      break;
    case kTp1:
      p.tau1_min = v;
      break;
    default:
      p.tau2_min = v;
      break;
  }
}

}  // namespace

double step_response(const TwoPoleDelay& p, double t_min) {
  const double tau = t_min - p.delay_min;
  if (!(tau > 0.0)) return 0.0;
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
      const double samples =
          std::ceil((e.value.delay_min + 7.0 * (e.value.tau1_min + e.value.tau2_min)) /
                    model.sample_time_min);
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
  Eigen::Matrix4d C = estimate.covariance;
  if (!C.diagonal().array().isFinite().any() && !C.diagonal().array().isInf().any()) {
    const TwoPoleDelay& se = estimate.std_error;  // no covariance: the standard errors alone
    C = Eigen::Vector4d(se.gain, se.delay_min, se.tau1_min, se.tau2_min)
            .array()
            .square()
            .matrix()
            .asDiagonal();
  }
  const TwoPoleDelay& p = estimate.value;
  // Central-difference steps: relative to the parameter, at least 1e-6 of the time scale.
  const double time_scale = std::max({p.delay_min, p.tau1_min, p.tau2_min, 1e-3});
  std::array<double, 4> h{};
  for (int k = 0; k < 4; ++k) {
    const double v = parameter(p, k);
    h[static_cast<std::size_t>(k)] =
        1e-6 * (k == kGain ? std::max(std::abs(v), 1e-12) : std::max(std::abs(v), time_scale));
  }
  for (const double t : times_min) {
    band.response.push_back(step_response(p, t));
    Eigen::Vector4d g;
    for (int k = 0; k < 4; ++k) {
      const double hk = h[static_cast<std::size_t>(k)];
      TwoPoleDelay up = p, down = p;
      set_parameter(up, k, parameter(p, k) + hk);
      // A time parameter at 0 is differentiated one-sided (it cannot go negative).
      const bool one_sided = k != kGain && parameter(p, k) - hk < 0.0;
      if (!one_sided) set_parameter(down, k, parameter(p, k) - hk);
      g(k) = (step_response(up, t) - step_response(down, t)) / (one_sided ? hk : 2.0 * hk);
    }
    double variance = 0.0;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
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
