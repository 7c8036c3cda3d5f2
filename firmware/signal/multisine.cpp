// SPDX-License-Identifier: MIT
#include "firmware/signal/multisine.hpp"

#include <algorithm>

#include "firmware/signal/trig.hpp"

namespace excite::signal {

void fill_unit_circle(std::span<double> cos_table, std::span<double> sin_table) {
  const std::size_t period = std::min(cos_table.size(), sin_table.size());
  for (std::size_t m = 0; m < period; ++m) {
    const CosSin cs = cos_sin_turn(m, period);
    cos_table[m] = cs.cos;
    sin_table[m] = cs.sin;
  }
}

void synthesize_period(std::span<const Line> lines, std::span<const double> cos_table,
                       std::span<const double> sin_table, std::span<double> period_out) {
  const std::size_t period = period_out.size();
  std::fill(period_out.begin(), period_out.end(), 0.0);
  if (period == 0) return;
  const double* cos_m = cos_table.data();
  const double* sin_m = sin_table.data();
  double* out = period_out.data();
  for (const Line& line : lines) {
    // A cos(θ + φ) = (A cos φ) cos θ − (A sin φ) sin θ, with θ = 2π (i · t mod P) / P.
    const CosSin phase = cos_sin(line.phase);
    const double a_cos = line.amplitude * phase.cos;
    const double a_sin = line.amplitude * phase.sin;
    const std::size_t step = line.index % period;
    std::size_t m = 0;
    for (std::size_t t = 0; t < period; ++t) {
      out[t] += a_cos * cos_m[m] - a_sin * sin_m[m];
      m += step;
      if (m >= period) m -= period;
    }
  }
}

}  // namespace excite::signal
