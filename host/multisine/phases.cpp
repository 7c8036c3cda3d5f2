// SPDX-License-Identifier: MIT
#include "host/multisine/phases.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"

namespace excite::host::multisine {
namespace {}  // namespace

std::vector<double> schroeder_phases(std::span<const double> amplitudes) {
  if (amplitudes.empty()) {
    throw std::invalid_argument("schroeder_phases: amplitudes: at least 1 line expected, got 0");
  }
  double total_power = 0.0;
  for (std::size_t k = 0; k < amplitudes.size(); ++k) {
    if (!(amplitudes[k] >= 0.0) || !std::isfinite(amplitudes[k])) {
      throw std::invalid_argument("schroeder_phases: amplitudes[" + std::to_string(k) +
                                  "] = " + config::format_number(amplitudes[k]) +
                                  ", expected a finite value >= 0");
    }
    total_power += amplitudes[k] * amplitudes[k];
  }
  if (total_power <= 0.0) {
    throw std::invalid_argument("schroeder_phases: amplitudes are all 0, expected some power");
  }
  // φ_n = −2π Σ_{j<n} ϑ_j (n − j), computed incrementally: with S_n = Σ_{j<n} ϑ_j,
  // φ_{n+1} − φ_n = −2π S_{n+1}.
  std::vector<double> phases(amplitudes.size());
  double cumulative = 0.0;  // Σ_{j ≤ n} ϑ_j
  double phase = 0.0;
  for (std::size_t n = 0; n < amplitudes.size(); ++n) {
    phases[n] = std::remainder(phase, 2.0 * std::numbers::pi);
    cumulative += amplitudes[n] * amplitudes[n] / total_power;
    phase -= 2.0 * std::numbers::pi * cumulative;
  }
  return phases;
}

std::vector<double> schroeder_phases_equal(std::uint32_t line_count) {
  if (line_count == 0) {
    throw std::invalid_argument("schroeder_phases_equal: line_count: at least 1 line expected");
  }
  std::vector<double> phases(line_count);
  const double count = line_count;
  for (std::uint32_t i = 0; i < line_count; ++i) {
    const double n = i + 1.0;
    phases[i] = std::remainder(-std::numbers::pi * n * (n - 1.0) / count, 2.0 * std::numbers::pi);
  }
  return phases;
}

std::vector<double> linear_phases(std::span<const std::uint32_t> indices, std::uint32_t period,
                                  double delay_samples) {
  if (period == 0) throw std::invalid_argument("linear_phases: period = 0, expected > 0 samples");
  std::vector<double> phases(indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const double omega = 2.0 * std::numbers::pi * indices[k] / period;  // rad/sample
    phases[k] = std::remainder(-delay_samples * omega, 2.0 * std::numbers::pi);
  }
  return phases;
}

std::vector<double> random_phases(std::uint32_t line_count, std::uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::vector<double> phases(line_count);
  for (auto& phase : phases) {
    // 53 random bits → [0, 1) exactly representable, then scaled to [0, 2π).
    const double unit = static_cast<double>(generator() >> 11U) * 0x1.0p-53;
    phase = 2.0 * std::numbers::pi * unit;
  }
  return phases;
}

std::vector<Line> make_lines(std::span<const std::uint32_t> indices,
                             std::span<const double> amplitudes, std::span<const double> phases) {
  auto check = [&](std::size_t count, const char* field) {
    if (count != indices.size()) {
      throw std::invalid_argument(
          std::string("make_lines: ") + field + ": " + std::to_string(count) + " values for " +
          std::to_string(indices.size()) + " line indices (count mismatch)");
    }
  };
  check(amplitudes.size(), "amplitudes");
  check(phases.size(), "phases");
  std::vector<Line> lines(indices.size());
  for (std::size_t k = 0; k < indices.size(); ++k)
    lines[k] = {indices[k], amplitudes[k], phases[k]};
  return lines;
}

void apply_schroeder(std::span<Line> lines) {
  std::vector<double> amplitudes(lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k) amplitudes[k] = lines[k].amplitude;
  const auto phases = schroeder_phases(amplitudes);
  for (std::size_t k = 0; k < lines.size(); ++k) lines[k].phase = phases[k];
}

}  // namespace excite::host::multisine
