// SPDX-License-Identifier: MIT
// The spread over seeds, Wilson intervals and T90's from-then-on definition.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/montecarlo/statistics.hpp"
#include "host/montecarlo/summary.hpp"

namespace mc = excite::host::montecarlo;

TEST(Spread, QuantilesInterpolateLinearlyBetweenTheSortedValues) {
  // 11 values 0…10 shuffled: position q·10 is the value itself.
  const mc::Spread s = mc::spread_of({7, 3, 10, 0, 5, 1, 9, 2, 8, 4, 6});
  EXPECT_DOUBLE_EQ(s.p10, 1.0);
  EXPECT_DOUBLE_EQ(s.median, 5.0);
  EXPECT_DOUBLE_EQ(s.p90, 9.0);
  // 4 values: median at position 1.5, p10 at 0.3, p90 at 2.7.
  const mc::Spread t = mc::spread_of({10, 0, 20, 30});
  EXPECT_DOUBLE_EQ(t.median, 15.0);
  EXPECT_DOUBLE_EQ(t.p10, 3.0);
  EXPECT_DOUBLE_EQ(t.p90, 27.0);
}

TEST(Spread, NonFiniteValuesAreLeftOutAndCounted) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const mc::Spread s = mc::spread_of({nan, 2.0, std::numeric_limits<double>::infinity(), 4.0});
  EXPECT_EQ(s.finite, 2);
  EXPECT_EQ(s.left_out, 2);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_TRUE(std::isnan(mc::spread_of({nan}).median));
}

TEST(Wilson, MatchesPublishedIntervals) {
  // Wilson 95 % for 9/10: 0.5958–0.9821; 0/10: 0–0.2775; 50/100: 0.4038–0.5962.
  mc::Interval w = mc::wilson95(9, 10);
  EXPECT_NEAR(w.low, 0.5958, 5e-5);
  EXPECT_NEAR(w.high, 0.9821, 5e-5);
  w = mc::wilson95(0, 10);
  EXPECT_DOUBLE_EQ(w.low, 0.0);
  EXPECT_NEAR(w.high, 0.2775, 5e-5);
  w = mc::wilson95(50, 100);
  EXPECT_NEAR(w.low, 0.4038, 5e-5);
  EXPECT_NEAR(w.high, 0.5962, 5e-5);
  EXPECT_THROW(mc::wilson95(3, 2), std::invalid_argument);
}

TEST(T90, IsTheFirstLengthFromWhichOnEveryShareIsAtLeastNinetyPercent) {
  EXPECT_EQ(mc::t90_index({0.2, 0.9, 0.95, 1.0}), std::optional<std::size_t>(1));
  // Rises above 90 % at index 1, falls back to 55 %: only index 3 on counts.
  EXPECT_EQ(mc::t90_index({0.5, 0.95, 0.55, 0.92, 0.96}), std::optional<std::size_t>(3));
  EXPECT_EQ(mc::t90_index({0.95, 0.95}), std::optional<std::size_t>(0));
}

TEST(T90, IsNoneWhenTheWholeRunIsBelowNinetyPercent) {
  EXPECT_EQ(mc::t90_index({0.95, 0.97, 0.89}), std::nullopt);
  EXPECT_EQ(mc::t90_index({}), std::nullopt);
}
