// SPDX-License-Identifier: MIT
#include "firmware/signal/multisine.hpp"

#include <algorithm>

#include "firmware/signal/trig.hpp"

namespace excite::signal {

void fill_unit_circle(std::span<double> unit_circle) {
  const std::size_t period = unit_circle.size() / 2;
  for (std::size_t m = 0; m < period; ++m) {
    const CosSin cs = cos_sin_turn(m, period);
    unit_circle[2 * m] = cs.cos;
    unit_circle[2 * m + 1] = cs.sin;
  }
}

void synthesize_period(std::span<const Line> lines, std::span<const double> unit_circle,
                       std::span<double> period_out) {
  const std::size_t period = period_out.size();
  std::fill(period_out.begin(), period_out.end(), 0.0);
  if (period == 0) return;
  const double* circle = unit_circle.data();
  double* out = period_out.data();
  const std::size_t end2 = 2 * period;

  // A cos(θ + φ) = (A cos φ) cos θ − (A sin φ) sin θ with θ = 2π (i · t mod P) / P; the
  // table index 2 · (i · t mod P) advances by 2i modulo 2P from one sample to the next.
  struct Walk {
    double a_cos;
    double a_sin;
    std::size_t step2;
    std::size_t m2 = 0;
    double next(const double* c, std::size_t end) {
      const double v = a_cos * c[m2] - a_sin * c[m2 + 1];
      m2 += step2;
      if (m2 >= end) m2 -= end;
      return v;
    }
  };
  const auto walk_of = [period](const Line& line) {
    const CosSin phase = cos_sin(line.phase);
    return Walk{line.amplitude * phase.cos, line.amplitude * phase.sin, 2 * (line.index % period)};
  };

  // Four lines per pass over the period for instruction-level parallelism; each out[t]
  // still receives the lines one by one in their order, so the sum is the same bits as a
  // line-by-line pass.
  std::size_t l = 0;
  for (; l + 4 <= lines.size(); l += 4) {
    Walk w0 = walk_of(lines[l]);
    Walk w1 = walk_of(lines[l + 1]);
    Walk w2 = walk_of(lines[l + 2]);
    Walk w3 = walk_of(lines[l + 3]);
    for (std::size_t t = 0; t < period; ++t) {
      const double v0 = w0.next(circle, end2);
      const double v1 = w1.next(circle, end2);
      const double v2 = w2.next(circle, end2);
      const double v3 = w3.next(circle, end2);
      out[t] = (((out[t] + v0) + v1) + v2) + v3;
    }
  }
  for (; l < lines.size(); ++l) {
    Walk w = walk_of(lines[l]);
    for (std::size_t t = 0; t < period; ++t) out[t] += w.next(circle, end2);
  }
}

}  // namespace excite::signal
