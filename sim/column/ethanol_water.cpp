// SPDX-License-Identifier: MIT
#include "sim/column/ethanol_water.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace excite::sim::column {
namespace {

// Antoine, log10(p / mmHg) = A − B / (C + t/°C); constants in README.md.
struct Antoine {
  double a, b, c;
};
constexpr Antoine kEthanol{8.20417, 1642.89, 230.300};
constexpr Antoine kWater{8.07131, 1730.63, 233.426};
constexpr double kKpaPerMmHg = 101.325 / 760.0;

// van Laar, natural-log form (README.md).
constexpr double kA12 = 1.6798;  // ethanol in water
constexpr double kA21 = 0.9227;  // water in ethanol

double antoine_kpa(const Antoine& k, double t_c) {
  return kKpaPerMmHg * std::pow(10.0, k.a - k.b / (k.c + t_c));
}
// d ln p / dT
double antoine_log_slope(const Antoine& k, double t_c) {
  return std::log(10.0) * k.b / ((k.c + t_c) * (k.c + t_c));
}

}  // namespace

double EthanolWater::ethanol_pressure_kpa(double t_c) {
  return antoine_kpa(kEthanol, t_c);
}
double EthanolWater::water_pressure_kpa(double t_c) {
  return antoine_kpa(kWater, t_c);
}

BubblePoint EthanolWater::bubble_point(double x) const {
  const double x1 = std::clamp(x, 0.0, 1.0);
  const double x2 = 1.0 - x1;
  const double d = kA12 * x1 + kA21 * x2;
  const double gamma1 = std::exp(kA12 * std::pow(kA21 * x2 / d, 2));
  const double gamma2 = std::exp(kA21 * std::pow(kA12 * x1 / d, 2));
  // Solve g(T) = ln(x₁γ₁p₁ + x₂γ₂p₂) − ln P = 0; g is increasing and nearly linear in T.
  double t = 85.0;
  for (int it = 0; it < 50; ++it) {
    const double p1 = x1 * gamma1 * antoine_kpa(kEthanol, t);
    const double p2 = x2 * gamma2 * antoine_kpa(kWater, t);
    const double total = p1 + p2;
    const double slope =
        (p1 * antoine_log_slope(kEthanol, t) + p2 * antoine_log_slope(kWater, t)) / total;
    const double dt = (std::log(total) - std::log(pressure_kpa_)) / slope;
    t -= dt;
    if (std::abs(dt) < 1e-12) break;
  }
  const double y = x1 * gamma1 * antoine_kpa(kEthanol, t) / pressure_kpa_;
  return BubblePoint{t, std::clamp(y, 0.0, 1.0)};
}

}  // namespace excite::sim::column
