// SPDX-License-Identifier: MIT
#include "firmware/plan/limits.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "example_plan.hpp"
#include "firmware/signal/generate.hpp"
#include "plan_table.hpp"

namespace excite::plan {
namespace {

using testing::example_plan;

using testing::table_of;

TEST(CheckLimits, AcceptsATableInsideEveryChannelsLimits) {
  const auto plan = example_plan();
  const std::vector<double> table = table_of(plan->recipe);
  const LimitCheck check = check_limits(*plan, {table.data(), 4, 4080});
  EXPECT_TRUE(check.status) << check.status.message();
}

TEST(CheckLimits, ReportsTheFirstViolationInTableOrder) {
  auto plan = example_plan();
  plan->meta.channels[2].max = 0.5;
  plan->meta.channels[1].min = -0.25;
  const std::vector<double> table = table_of(plan->recipe);
  std::uint32_t first_k = 0;
  std::uint32_t first_c = 0;
  [&] {
    for (std::uint32_t k = 0; k < 4080; ++k) {
      for (std::uint32_t c = 0; c < 4; ++c) {
        const double v = table[4 * k + c];
        if (v < plan->meta.channels[c].min || v > plan->meta.channels[c].max) {
          first_k = k;
          first_c = c;
          return;
        }
      }
    }
    FAIL() << "the narrowed limits should be violated";
  }();
  const LimitCheck check = check_limits(*plan, {table.data(), 4, 4080});
  EXPECT_EQ(check.status.code(), StatusCode::limit_violated);
  EXPECT_EQ(check.sample, first_k);
  EXPECT_EQ(check.channel, first_c);
  EXPECT_EQ(check.value, table[4 * first_k + first_c]);
}

TEST(CheckLimits, NamesSampleChannelValueAndLimitsInTheMessage) {
  auto plan = example_plan();
  std::vector<double> table(4 * 4080, 0.0);
  table[4 * 117 + 2] = 12.5;  // channel 2 "side draw S" allows [-12, 12]
  const LimitCheck check = check_limits(*plan, {table.data(), 4, 4080});
  EXPECT_EQ(std::string(check.status.message()),
            "table(sample 117, channel 2 \"side draw S\") = 12.5, expected within [-12, 12]");
}

TEST(CheckLimits, CountsNaNAsOutside) {
  auto plan = example_plan();
  std::vector<double> table(4 * 4080, 0.0);
  table[4 * 9 + 0] = std::numeric_limits<double>::quiet_NaN();
  const LimitCheck check = check_limits(*plan, {table.data(), 4, 4080});
  EXPECT_EQ(check.status.code(), StatusCode::limit_violated);
  EXPECT_EQ(check.sample, 9U);
}

TEST(CheckLimits, AcceptsValuesExactlyOnTheLimits) {
  auto plan = example_plan();
  std::vector<double> table(4 * 4080, 0.0);
  table[0] = -10.0;
  table[1] = 11.0;
  EXPECT_TRUE(check_limits(*plan, {table.data(), 4, 4080}).status);
}

TEST(CheckLimits, RefusesATableOfAnotherShape) {
  const auto plan = example_plan();
  std::vector<double> table(4 * 4000, 0.0);
  EXPECT_EQ(std::string(check_limits(*plan, {table.data(), 4, 4000}).status.message()),
            "table of 4 channels × 4000 samples, expected the plan's 4 × 4080");
}

}  // namespace
}  // namespace excite::plan
