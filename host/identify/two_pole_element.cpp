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

DiscreteTwoPole discretise(const TwoPoleDelay& g, double sample_time_min) {
  const double T = sample_time_min;
  DiscreteTwoPole c;
  const double f1 = g.tp1_min < kTinyTimeConstant ? 0.0 : std::exp(-T / g.tp1_min);
  const double f2 = g.tp2_min < kTinyTimeConstant ? 0.0 : std::exp(-T / g.tp2_min);
  c.a1 = -(f1 + f2);
  c.a2 = f1 * f2;
  const double d_real = std::floor(g.delay_min / T);
  c.delay_samples = static_cast<std::size_t>(std::max(0.0, d_real));
  const auto d = static_cast<double>(c.delay_samples);
  // Pulse response h(m) = S(mT) − S((m−1)T) of the delayed element (S includes T_d).
  const auto h = [&](double m) {
    return step_response(g, m * T) - step_response(g, (m - 1.0) * T);
  };
  for (std::size_t j = 0; j < 4; ++j) {
    const double m = d + static_cast<double>(j);
    c.b[j] = h(m) + c.a1 * h(m - 1.0) + c.a2 * h(m - 2.0);
  }
  return c;
}

void simulate(const DiscreteTwoPole& g, const double* u, std::ptrdiff_t u_stride, double* y,
              std::ptrdiff_t y_stride, std::size_t n, bool accumulate) {
  const std::size_t d = g.delay_samples;
  double y1 = 0.0;  // y(k−1)
  double y2 = 0.0;  // y(k−2)
  const auto at = [&](std::size_t k) { return u[static_cast<std::ptrdiff_t>(k) * u_stride]; };
  for (std::size_t k = 0; k < n; ++k) {
    double x = 0.0;
    // Σ_j b_j u(k − d − j) over the taps that exist (u = 0 before k = 0).
    if (k >= d) {
      const std::size_t top = std::min<std::size_t>(3, k - d);
      for (std::size_t j = 0; j <= top; ++j) x += g.b[j] * at(k - d - j);
    }
    const double yk = x - g.a1 * y1 - g.a2 * y2;
    y2 = y1;
    y1 = yk;
    double& out = y[static_cast<std::ptrdiff_t>(k) * y_stride];
    out = accumulate ? out + yk : yk;
  }
}

}  // namespace excite::host
