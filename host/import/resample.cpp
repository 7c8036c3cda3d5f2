// SPDX-License-Identifier: MIT
#include "host/import/resample.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace excite::host::historian {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Grid and sample times closer than this (seconds) are the same instant.
constexpr double kSameInstant = 1e-6;
}  // namespace

std::vector<double> resample(std::span<const double> time_s, std::span<const double> values,
                             std::span<const double> grid_s, Resample mode, double gap_limit_s) {
  std::vector<double> out(grid_s.size(), kNaN);
  std::size_t next = 0;  // first sample after the grid point
  for (std::size_t k = 0; k < grid_s.size(); ++k) {
    const double t = grid_s[k];
    while (next < time_s.size() && time_s[next] <= t + kSameInstant) ++next;
    if (next == 0) continue;  // no sample at or before t
    const std::size_t prev = next - 1;
    const double age = t - time_s[prev];
    if (mode == Resample::hold || std::abs(age) <= kSameInstant) {
      if (age <= gap_limit_s) out[k] = values[prev];
      continue;
    }
    if (next == time_s.size() || time_s[next] - time_s[prev] > gap_limit_s) continue;
    const double w = age / (time_s[next] - time_s[prev]);
    out[k] = values[prev] + w * (values[next] - values[prev]);  // NaN when either is bad
  }
  return out;
}

double median_spacing(std::span<const double> time_s) {
  if (time_s.size() < 2) return 0.0;
  std::vector<double> d;
  for (std::size_t i = 1; i < time_s.size(); ++i) d.push_back(time_s[i] - time_s[i - 1]);
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace excite::host::historian
