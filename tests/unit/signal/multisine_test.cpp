// SPDX-License-Identifier: MIT
#include "firmware/signal/multisine.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace excite::signal {
namespace {

constexpr long double kTwoPiL = 6.283185307179586476925286766559L;

std::vector<Line> random_lines(std::uint32_t period, std::size_t count, double phase_range,
                               std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> index(0, (period - 1) / 2);
  std::uniform_real_distribution<double> amplitude(-1.0, 1.0);
  std::uniform_real_distribution<double> phase(-phase_range, phase_range);
  std::vector<Line> lines(count);
  for (Line& l : lines) l = {index(rng), amplitude(rng), phase(rng)};
  return lines;
}

std::vector<double> synthesize(const std::vector<Line>& lines, std::uint32_t period) {
  std::vector<double> unit_circle(2 * std::size_t{period});
  std::vector<double> out(period);
  fill_unit_circle(unit_circle);
  synthesize_period(lines, unit_circle, out);
  return out;
}

// Oracle: the direct sum of 4.2.9 in long double, one libm call per line and sample.
long double direct_sum(const std::vector<Line>& lines, std::uint32_t period, std::uint32_t t) {
  long double sum = 0.0L;
  for (const Line& l : lines) {
    const auto m = static_cast<long double>((std::uint64_t{l.index} * t) % period);
    sum += l.amplitude * std::cos(kTwoPiL * m / period + static_cast<long double>(l.phase));
  }
  return sum;
}

double scale_of(const std::vector<Line>& lines) {
  double scale = 0.0;
  for (const Line& l : lines) scale += std::fabs(l.amplitude);
  return scale;
}

class MultisineOfPeriod : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(MultisineOfPeriod, MatchesTheDirectCosineSumWithin1e12OfTheAmplitudeSum) {
  const std::uint32_t period = GetParam();
  // 61 lines: fifteen four-line passes and one line on its own.
  const std::vector<Line> lines = random_lines(period, 61, 1e3, period);
  const std::vector<double> x = synthesize(lines, period);
  const double tolerance = 1e-12 * scale_of(lines);
  for (std::uint32_t t = 0; t < period; ++t) {
    ASSERT_NEAR(x[t], static_cast<double>(direct_sum(lines, period, t)), tolerance) << "t " << t;
  }
}

INSTANTIATE_TEST_SUITE_P(EvenOddAndCaseStudyPeriods, MultisineOfPeriod,
                         ::testing::Values(2U, 3U, 63U, 1001U, 4080U));

TEST(Multisine, WithoutLinesIsZero) {
  const std::vector<double> x = synthesize({}, 16);
  for (const double v : x) EXPECT_EQ(v, 0.0);
}

TEST(Multisine, SingleLineOfIndexOneIsOneCosinePeriod) {
  const std::vector<double> x = synthesize({{1, 2.0, 0.0}}, 8);
  const double h = 2.0 * std::numbers::sqrt2 / 2.0;
  const std::vector<double> expected = {2.0, h, 0.0, -h, -2.0, -h, 0.0, h};
  for (std::size_t t = 0; t < 8; ++t) EXPECT_NEAR(x[t], expected[t], 1e-15) << t;
}

}  // namespace
}  // namespace excite::signal
