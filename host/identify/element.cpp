// SPDX-License-Identifier: MIT
#include "host/identify/element.hpp"

#include <algorithm>

namespace excite::host {

sim::DiscreteTerm discretise(const TwoPoleDelay& g, double sample_time_min) {
  TwoPoleDelay p = g;
  const double tiny = kVanishingTimeConstant * sample_time_min;
  if (p.tau1_min < tiny) p.tau1_min = 0.0;
  if (p.tau2_min < tiny) p.tau2_min = 0.0;
  return sim::discretise_sopdt(p, sample_time_min);
}

void simulate(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y) {
  sim::simulate_term(g, u.data(), y.data(), std::min(u.size(), y.size()));
}

LagTaps lag_taps(const TwoPoleDelay& g, double sample_time_min, std::size_t first_lag) {
  const sim::DiscreteTerm d = discretise(g, sample_time_min);
  LagTaps t;
  t.a1 = d.na > 1 ? d.a[1] : 0.0;
  t.a2 = d.na > 2 ? d.a[2] : 0.0;
  for (int i = 0; i < d.nb; ++i) {
    const auto lag = static_cast<std::size_t>(d.delay_samples + i);
    if (lag >= first_lag && lag < first_lag + kLagWindow)
      t.b[lag - first_lag] = d.b[static_cast<std::size_t>(i)];
  }
  return t;
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

}  // namespace excite::host
