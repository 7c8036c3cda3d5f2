// SPDX-License-Identifier: MIT
#include "host/identify/two_pole_element.hpp"

#include <algorithm>
#include <cmath>

namespace excite::host {
namespace {

// Below this a time constant is treated as exactly zero (1/T_p would overflow).
constexpr double kTinyTimeConstant = 1e-200;

// (1 − e^{−x}) / x for x ≥ 0, accurate at x → 0.
double phi1(double x) {
  return x > 0.0 ? -std::expm1(-x) / x : 1.0;
}

// (e^{−pt} − e^{−qt}) / (q − p) for rates p, q ≥ 0, t > 0: the divided difference of the
// exponential, finite and accurate for p = q (→ t e^{−pt}) and p ≈ q.
double exp_divided_difference(double p, double q, double t) {
  const double lo = std::min(p, q);
  const double gap = std::abs(q - p);
  return std::exp(-lo * t) * t * phi1(gap * t);
}

// g(t) = (a e^{−t/a} − b e^{−t/b}) / (a − b) for t > 0, i.e. 1 − S(t)/K, in rates.
double unit_decay(double tp1, double tp2, double t) {
  const bool zero1 = tp1 < kTinyTimeConstant;
  const bool zero2 = tp2 < kTinyTimeConstant;
  if (zero1 && zero2) return 0.0;
  if (zero1) return std::exp(-t / tp2);
  if (zero2) return std::exp(-t / tp1);
  const double p = 1.0 / tp1;
  const double q = 1.0 / tp2;
  // g = e^{−pt} + p · (e^{−pt} − e^{−qt}) / (q − p); symmetric in p, q.
  return std::exp(-p * t) + p * exp_divided_difference(p, q, t);
}

}  // namespace

double step_response(const TwoPoleDelay& g, double t_min) {
  const double t = t_min - g.delay_min;
  if (t < 0.0) return 0.0;
  if (t == 0.0) {
    // Strictly proper elements start at 0; a pure gain (both time constants zero) jumps.
    const bool static_gain = g.tp1_min < kTinyTimeConstant && g.tp2_min < kTinyTimeConstant;
    return static_gain ? g.gain : 0.0;
  }
  return g.gain * (1.0 - unit_decay(g.tp1_min, g.tp2_min, t));
}

double numerator_tap(const TwoPoleDelay& g, double sample_time_min, double a1, double a2,
                     std::size_t m) {
  const double T = sample_time_min;
  // Pulse response h(m) = S(mT) − S((m−1)T) of the delayed element (S includes T_d).
  const auto h = [&](double j) {
    return step_response(g, j * T) - step_response(g, (j - 1.0) * T);
  };
  const auto mm = static_cast<double>(m);
  return h(mm) + a1 * h(mm - 1.0) + a2 * h(mm - 2.0);
}

std::array<double, 2> denominator(const TwoPoleDelay& g, double sample_time_min) {
  const double T = sample_time_min;
  const double f1 = g.tp1_min < kTinyTimeConstant ? 0.0 : std::exp(-T / g.tp1_min);
  const double f2 = g.tp2_min < kTinyTimeConstant ? 0.0 : std::exp(-T / g.tp2_min);
  return {-(f1 + f2), f1 * f2};
}

DiscreteTwoPole discretise(const TwoPoleDelay& g, double sample_time_min) {
  const double T = sample_time_min;
  DiscreteTwoPole c;
  const auto [a1, a2] = denominator(g, T);
  c.a1 = a1;
  c.a2 = a2;
  c.delay_samples = static_cast<std::size_t>(std::max(0.0, std::floor(g.delay_min / T)));
  for (std::size_t j = 0; j < 4; ++j) {
    c.b[j] = numerator_tap(g, T, c.a1, c.a2, c.delay_samples + j);
  }
  return c;
}

void all_pole_filter(double a1, double a2, std::span<double> x) {
  double y1 = 0.0;  // y(k−1)
  double y2 = 0.0;  // y(k−2)
  for (double& v : x) {
    const double yk = (v - a2 * y2) - a1 * y1;
    y2 = y1;
    y1 = yk;
    v = yk;
  }
}

void simulate(const DiscreteTwoPole& g, std::span<const double> u, std::span<double> y) {
  const std::size_t n = std::min(u.size(), y.size());
  std::fill(y.begin(), y.end(), 0.0);
  // FIR part Σ_j b_j u(k − d − j) (u = 0 before k = 0), then the poles in place.
  for (std::size_t j = 0; j < 4; ++j) {
    const std::size_t lag = g.delay_samples + j;
    const double b = g.b[j];
    if (b == 0.0) continue;
    for (std::size_t k = lag; k < n; ++k) y[k] += b * u[k - lag];
  }
  all_pole_filter(g.a1, g.a2, y.first(n));
}

}  // namespace excite::host
