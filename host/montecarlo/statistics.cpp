// SPDX-License-Identifier: MIT
#include "host/montecarlo/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace excite::host::montecarlo {
namespace {

double quantile(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double t = position - static_cast<double>(below);
  return sorted[below] + t * (sorted[above] - sorted[below]);
}

}  // namespace

Spread spread_of(std::vector<double> values) {
  Spread s;
  const auto finite_end =
      std::partition(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
  s.left_out = static_cast<int>(values.end() - finite_end);
  values.erase(finite_end, values.end());
  s.finite = static_cast<int>(values.size());
  if (values.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.p10 = s.median = s.p90 = s.p25 = s.p75 = nan;
    return s;
  }
  std::sort(values.begin(), values.end());
  s.p10 = quantile(values, 0.10);
  s.median = quantile(values, 0.50);
  s.p90 = quantile(values, 0.90);
  s.p25 = quantile(values, 0.25);
  s.p75 = quantile(values, 0.75);
  return s;
}

Interval wilson95(int k, int n) {
  if (n < 0 || k < 0 || k > n) {
    throw std::invalid_argument("wilson95: k = " + std::to_string(k) +
                                " of n = " + std::to_string(n) + ", expected 0 <= k <= n");
  }
  if (n == 0) return {};
  constexpr double z = 1.959963984540054;
  const double nn = n;
  const double p = k / nn;
  const double denominator = 1.0 + z * z / nn;
  const double centre = (p + z * z / (2.0 * nn)) / denominator;
  const double half = z / denominator * std::sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace excite::host::montecarlo
