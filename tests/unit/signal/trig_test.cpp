// SPDX-License-Identifier: MIT
#include "firmware/signal/trig.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace excite::signal {
namespace {

constexpr long double kTwoPi = 6.283185307179586476925286766559L;

TEST(CosSinTurn, AgreesWithLongDoubleCosineOnEveryGridPointWithin2e16) {
  if (std::numeric_limits<long double>::digits <= std::numeric_limits<double>::digits) {
    GTEST_SKIP() << "long double is no wider than double on this target (armhf): no reference";
  }
  for (const std::uint64_t period : {2U, 3U, 7U, 8U, 1001U, 4080U}) {
    for (std::uint64_t m = 0; m < period; ++m) {
      const CosSin cs = cos_sin_turn(m, period);
      const long double angle =
          kTwoPi * static_cast<long double>(m) / static_cast<long double>(period);
      ASSERT_NEAR(cs.cos, static_cast<double>(std::cos(angle)), 2e-16) << m << "/" << period;
      ASSERT_NEAR(cs.sin, static_cast<double>(std::sin(angle)), 2e-16) << m << "/" << period;
    }
  }
}

TEST(CosSinTurn, IsExactOnQuarterTurns) {
  EXPECT_EQ(cos_sin_turn(0, 12).cos, 1.0);
  EXPECT_EQ(cos_sin_turn(0, 12).sin, 0.0);
  EXPECT_EQ(cos_sin_turn(3, 12).cos, 0.0);
  EXPECT_EQ(cos_sin_turn(3, 12).sin, 1.0);
  EXPECT_EQ(cos_sin_turn(6, 12).cos, -1.0);
  EXPECT_EQ(cos_sin_turn(9, 12).sin, -1.0);
}

TEST(CosSinTurn, ReducesMModuloThePeriodExactly) {
  const CosSin a = cos_sin_turn(5, 17);
  const CosSin b = cos_sin_turn(5 + 17ULL * 123456789ULL, 17);
  EXPECT_EQ(a.cos, b.cos);
  EXPECT_EQ(a.sin, b.sin);
}

TEST(CosSin, AgreesWithLongDoubleCosineUpToTheLargestArgumentWithin1e15) {
  std::mt19937 rng(7);
  for (const double range : {1.0, 10.0, 1e3, kMaxTrigArgument}) {
    std::uniform_real_distribution<double> x_of(-range, range);
    for (int n = 0; n < 20000; ++n) {
      const double x = x_of(rng);
      const CosSin cs = cos_sin(x);
      const long double xl = x;
      ASSERT_NEAR(cs.cos, static_cast<double>(std::cos(xl)), 1e-15) << x;
      ASSERT_NEAR(cs.sin, static_cast<double>(std::sin(xl)), 1e-15) << x;
    }
  }
}

}  // namespace
}  // namespace excite::signal
