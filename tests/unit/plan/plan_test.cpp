// SPDX-License-Identifier: MIT
#include "firmware/plan/plan.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "example_plan.hpp"

namespace excite::plan {
namespace {

using testing::example_plan;

TEST(PlanValidate, AcceptsTheExamplePlan) {
  const Status status = validate(*example_plan());
  EXPECT_TRUE(status) << status.message();
}

TEST(PlanValidate, PassesOnTheRecipesFirstError) {
  auto plan = example_plan();
  plan->recipe.sources[0].prbs.hold_samples = 0;
  EXPECT_EQ(std::string(validate(*plan).message()),
            "sources[0].prbs.hold_samples = 0, expected ≥ 1");
}

TEST(PlanValidate, RefusesANonPositiveSampleTime) {
  auto plan = example_plan();
  plan->meta.sample_time_min = -1.0;
  EXPECT_EQ(std::string(validate(*plan).message()),
            "meta.sample_time_min = -1, expected a finite number > 0");
}

TEST(PlanValidate, RefusesAChannelWhoseMinExceedsItsMax) {
  auto plan = example_plan();
  plan->meta.channels[1].min = 3.0;
  plan->meta.channels[1].max = 2.0;
  EXPECT_EQ(std::string(validate(*plan).message()), "meta.channels[1].min = 3, expected ≤ max = 2");
}

TEST(PlanValidate, RefusesANonFiniteLimit) {
  auto plan = example_plan();
  plan->meta.channels[3].max = std::numeric_limits<double>::infinity();
  EXPECT_EQ(std::string(validate(*plan).message()),
            "meta.channels[3].max = inf, expected a finite number");
}

TEST(PlanValidate, RefusesANameWithoutTerminatingNul) {
  auto plan = example_plan();
  plan->meta.channels[2].name.fill('x');
  EXPECT_EQ(std::string(validate(*plan).message()),
            "meta.channels[2].name has no terminating NUL, expected ≤ 31 bytes");
}

TEST(PlanValidate, RefusesFormatVersionZero) {
  auto plan = example_plan();
  plan->meta.format_version = 0;
  EXPECT_EQ(validate(*plan).code(), StatusCode::unsupported_version);
}

TEST(PlanText, HoldsAtMost31BytesInA32ByteField) {
  Text<kNameCapacity> name{};
  EXPECT_TRUE(set_text(name, std::string(31, 'a')));
  EXPECT_EQ(text_of(name), std::string(31, 'a'));
  EXPECT_FALSE(set_text(name, std::string(32, 'b')));
  EXPECT_EQ(text_of(name), std::string(31, 'a'));  // unchanged
}

TEST(PlanText, RefusesAnEmbeddedNul) {
  Text<kNameCapacity> name{};
  EXPECT_FALSE(set_text(name, std::string_view("a\0b", 3)));
}

}  // namespace
}  // namespace excite::plan
