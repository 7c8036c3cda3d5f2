// SPDX-License-Identifier: MIT
#include "host/multisine/synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/FFT>

namespace excite::host::multisine {

void validate_lines(std::span<const Line> lines, std::uint32_t period, std::string_view what) {
  const std::string where(what);
  if (period == 0) throw std::invalid_argument(where + ": period = 0, expected > 0 samples");
  if (lines.empty()) {
    throw std::invalid_argument(where + ": lines: too few lines, expected at least 1, got 0");
  }
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const Line& line = lines[k];
    const std::string name = where + ": lines[" + std::to_string(k) + "]";
    if (line.index == 0) {
      throw std::invalid_argument(name + ".index = 0: the DC line is not a multisine line");
    }
    if (2ULL * line.index >= period) {
      throw std::invalid_argument(
          name + ".index = " + std::to_string(line.index) +
          ": band beyond Nyquist, expected index < period/2 = " + std::to_string(period / 2.0) +
          " (period " + std::to_string(period) + " samples)");
    }
    if (!(line.amplitude >= 0.0) || !std::isfinite(line.amplitude)) {
      throw std::invalid_argument(name + ".amplitude = " + std::to_string(line.amplitude) +
                                  ", expected a finite value >= 0");
    }
    if (!std::isfinite(line.phase)) {
      throw std::invalid_argument(name + ".phase is not finite");
    }
  }
}

std::vector<double> synthesize(std::span<const Line> lines, std::uint32_t period) {
  validate_lines(lines, period, "synthesize");
  std::vector<double> cos_table(period);
  std::vector<double> sin_table(period);
  for (std::uint32_t m = 0; m < period; ++m) {
    const double angle = 2.0 * std::numbers::pi * m / period;
    cos_table[m] = std::cos(angle);
    sin_table[m] = std::sin(angle);
  }
  std::vector<double> x(period, 0.0);
  for (const Line& line : lines) {
    const double c = line.amplitude * std::cos(line.phase);
    const double s = line.amplitude * std::sin(line.phase);
    std::uint64_t position = 0;  // index · t mod P, kept exact in integers
    for (std::uint32_t t = 0; t < period; ++t) {
      x[t] += c * cos_table[position] - s * sin_table[position];
      position += line.index;
      if (position >= period) position -= period;
    }
  }
  return x;
}

std::vector<double> synthesize_on_grid(std::span<const Line> lines, std::uint32_t period,
                                       std::uint32_t grid) {
  validate_lines(lines, period, "synthesize_on_grid");
  std::uint32_t top = 0;
  for (const Line& line : lines) top = std::max(top, line.index);
  if (grid % 2 != 0 || grid <= 2 * top) {
    throw std::invalid_argument("synthesize_on_grid: grid = " + std::to_string(grid) +
                                ", expected even and > 2 · max index = " + std::to_string(2 * top));
  }
  std::vector<std::complex<double>> spectrum(grid / 2 + 1, {0.0, 0.0});
  for (const Line& line : lines)
    spectrum[line.index] += std::polar(line.amplitude / 2.0, line.phase);
  Eigen::FFT<double> fft;
  fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
  fft.SetFlag(Eigen::FFT<double>::Unscaled);
  std::vector<double> x(grid);
  fft.inv(x.data(), spectrum.data(), grid);
  return x;
}

double crest_factor(std::span<const double> samples) {
  if (samples.empty())
    throw std::invalid_argument("crest_factor: samples = 0 (none), expected at least 1");
  double peak = 0.0;
  double sum_squares = 0.0;
  for (double v : samples) {
    peak = std::max(peak, std::abs(v));
    sum_squares += v * v;
  }
  if (sum_squares <= 0.0) throw std::invalid_argument("crest_factor: samples are all 0");
  return peak / std::sqrt(sum_squares / static_cast<double>(samples.size()));
}

double cf_sampled(std::span<const Line> lines, std::uint32_t period) {
  const auto x = synthesize(lines, period);
  return crest_factor(x);
}

std::uint32_t continuous_grid(std::span<const Line> lines, std::uint32_t period,
                              std::uint32_t oversampling) {
  std::uint64_t top = 0;
  for (const Line& line : lines) top = std::max<std::uint64_t>(top, line.index);
  const std::uint64_t wanted = std::max<std::uint64_t>(
      std::uint64_t{std::max<std::uint32_t>(oversampling, 1)} * period, 32 * top);
  std::uint64_t grid = 2;
  while (grid < wanted) grid *= 2;
  if (grid > (std::uint64_t{1} << 30)) {
    throw std::invalid_argument("cf_continuous: grid of " + std::to_string(grid) +
                                " points is too large (period " + std::to_string(period) + ")");
  }
  return static_cast<std::uint32_t>(grid);
}

double cf_continuous(std::span<const Line> lines, std::uint32_t period,
                     std::uint32_t oversampling) {
  validate_lines(lines, period, "cf_continuous");
  const auto x = synthesize_on_grid(lines, period, continuous_grid(lines, period, oversampling));
  double power = 0.0;
  for (const Line& line : lines) power += line.amplitude * line.amplitude / 2.0;
  if (power <= 0.0) throw std::invalid_argument("cf_continuous: lines carry no power");
  double peak = 0.0;
  for (double v : x) peak = std::max(peak, std::abs(v));
  return peak / std::sqrt(power);
}

}  // namespace excite::host::multisine
