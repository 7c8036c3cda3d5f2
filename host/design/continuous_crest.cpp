// SPDX-License-Identifier: MIT
#include "host/design/continuous_crest.hpp"

#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <tuple>

#include "host/multisine/synthesis.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Sources active over the same samples with the same period add up line by line.
using WindowKey = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;  // start, length, period

double channel_peak(const signal::Recipe& r, std::uint32_t c, bool& multisine_only) {
  std::map<WindowKey, std::map<std::uint32_t, std::complex<double>>> windows;
  for (std::uint32_t i = 0; i < r.source_count; ++i) {
    const double weight = r.mix[c][i];
    if (weight == 0.0) continue;
    const signal::Source& s = r.sources[i];
    if (s.kind != signal::SourceKind::multisine) {
      multisine_only = false;
      return kNaN;
    }
    auto& phasors = windows[{s.start, s.length, s.multisine.period}];
    for (std::uint32_t l = 0; l < s.multisine.line_count; ++l) {
      const signal::Line& line = r.lines[s.multisine.first_line + l];
      phasors[line.index] += weight * std::polar(line.amplitude, line.phase);
    }
  }
  double peak = 0.0;
  for (const auto& [key, phasors] : windows) {
    std::vector<signal::Line> lines;
    for (const auto& [index, z] : phasors) {
      if (std::abs(z) > 0.0) lines.push_back({index, std::abs(z), std::arg(z)});
    }
    if (lines.empty()) continue;
    const std::uint32_t period = std::get<2>(key);
    const std::uint32_t grid =
        multisine::continuous_grid(lines, period, multisine::kContinuousOversampling);
    for (const double x : multisine::synthesize_on_grid(lines, period, grid))
      peak = std::max(peak, std::abs(x));
  }
  return peak;
}

}  // namespace

std::vector<double> continuous_crest_factors(const signal::Recipe& recipe, const Table& table) {
  std::vector<double> cf(recipe.channels, kNaN);
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    bool multisine_only = true;
    const double peak = channel_peak(recipe, c, multisine_only);
    const double rms = std::sqrt(table.col(c).squaredNorm() / static_cast<double>(table.rows()));
    if (multisine_only && peak > 0.0 && rms > 0.0) cf[c] = peak / rms;
  }
  return cf;
}

}  // namespace excite::host
