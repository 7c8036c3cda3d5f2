// SPDX-License-Identifier: MIT
#include "firmware/signal/validate.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "example_recipes.hpp"

namespace excite::signal {
namespace {

using testing::mixed_case_study_recipe;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Validate, AcceptsTheMixedCaseStudyRecipe) {
  const Status status = validate(*mixed_case_study_recipe(), 4 * 4080);
  EXPECT_TRUE(status) << status.message();
  EXPECT_STREQ(status.message(), "");
}

TEST(Validate, IgnoresUnusedEntriesBeyondTheCounts) {
  auto recipe = mixed_case_study_recipe();
  recipe->sources[10].prbs.register_length = 99;  // source_count = 5
  recipe->lines[500].amplitude = kNaN;            // line_count = 120
  recipe->mix[5][0] = kNaN;                       // channels = 4
  recipe->mix[0][7] = kNaN;
  EXPECT_TRUE(validate(*recipe));
}

// One broken field per case, on the mixed case-study recipe: sources 0, 1 PRBS (n_r 8),
// 2, 3 multisines (lines 0–59, 60–119, period 4080), 4 steps in [330, 1650).
struct BadField {
  const char* name;
  void (*spoil)(Recipe&);
  StatusCode code;
  const char* message;
  std::size_t capacity = kUnlimited;
};

class ValidateRefuses : public ::testing::TestWithParam<BadField> {};

TEST_P(ValidateRefuses, NamingTheFieldTheValueAndWhatWasExpected) {
  auto recipe = mixed_case_study_recipe();
  GetParam().spoil(*recipe);
  const Status status = validate(*recipe, GetParam().capacity);
  EXPECT_FALSE(status);
  EXPECT_EQ(status.code(), GetParam().code);
  EXPECT_EQ(std::string(status.message()), GetParam().message);
}

const BadField kBadFields[] = {
    {"NoChannels", [](Recipe& r) { r.channels = 0; }, StatusCode::invalid_field,
     "channels = 0, expected 1…8"},
    {"TooManyChannels", [](Recipe& r) { r.channels = 9; }, StatusCode::invalid_field,
     "channels = 9, expected 1…8"},
    {"NoSamples", [](Recipe& r) { r.samples = 0; }, StatusCode::invalid_field,
     "samples = 0, expected ≥ 1"},
    {"TableBeyondCapacity", [](Recipe&) {}, StatusCode::capacity_exceeded,
     "table of channels × samples = 4 × 4080 = 16320 values, expected ≤ capacity 16319",
     4 * 4080 - 1},
    {"TooManySources", [](Recipe& r) { r.source_count = 17; }, StatusCode::capacity_exceeded,
     "source_count = 17, expected ≤ 16"},
    {"TooManyLines", [](Recipe& r) { r.line_count = 4097; }, StatusCode::capacity_exceeded,
     "line_count = 4097, expected ≤ 4096"},
    {"SourceWithoutKind", [](Recipe& r) { r.sources[1].kind = SourceKind::none; },
     StatusCode::invalid_field,
     "sources[1].kind = 0, expected 1 (steps), 2 (prbs) or 3 (multisine)"},
    {"WindowBeyondTheTable", [](Recipe& r) { r.sources[4].start = 3000; },
     StatusCode::invalid_field,
     "sources[4].start + length = 3000 + 1320 = 4320, expected ≤ samples = 4080"},
    {"RegisterLengthBeyond31", [](Recipe& r) { r.sources[1].prbs.register_length = 40; },
     StatusCode::invalid_field, "sources[1].prbs.register_length = 40, expected 2…31"},
    {"RegisterLengthBelow2", [](Recipe& r) { r.sources[0].prbs.register_length = 1; },
     StatusCode::invalid_field, "sources[0].prbs.register_length = 1, expected 2…31"},
    {"PrbsAmplitudeNaN", [](Recipe& r) { r.sources[0].prbs.amplitude = kNaN; },
     StatusCode::invalid_field, "sources[0].prbs.amplitude = nan, expected a finite number"},
    {"HoldOfZeroSamples", [](Recipe& r) { r.sources[0].prbs.hold_samples = 0; },
     StatusCode::invalid_field, "sources[0].prbs.hold_samples = 0, expected ≥ 1"},
    {"ShiftOfAWholePeriod", [](Recipe& r) { r.sources[1].prbs.shift = 255; },
     StatusCode::invalid_field, "sources[1].prbs.shift = 255, expected < 2^8 − 1 = 255 bits"},
    {"TooManySegments", [](Recipe& r) { r.sources[4].steps.segment_count = 65; },
     StatusCode::capacity_exceeded, "sources[4].steps.segment_count = 65, expected ≤ 64"},
    {"SegmentLevelInfinite", [](Recipe& r) { r.sources[4].steps.segments[2].level = kInf; },
     StatusCode::invalid_field,
     "sources[4].steps.segments[2].level = inf, expected a finite number"},
    {"PeriodLongerThanTheTable", [](Recipe& r) { r.sources[2].multisine.period = 4081; },
     StatusCode::invalid_field, "sources[2].multisine.period = 4081, expected 2…samples = 4080"},
    {"PeriodOfOneSample", [](Recipe& r) { r.sources[3].multisine.period = 1; },
     StatusCode::invalid_field, "sources[3].multisine.period = 1, expected 2…samples = 4080"},
    {"LineRangeBeyondLineCount", [](Recipe& r) { r.sources[3].multisine.line_count = 61; },
     StatusCode::invalid_field,
     "sources[3].multisine.first_line + line_count = 60 + 61 = 121, expected ≤ line_count = "
     "120"},
    {"LineAtNyquist", [](Recipe& r) { r.lines[5].index = 2040; }, StatusCode::invalid_field,
     "lines[5].index = 2040, expected < period/2 = 2040 (Nyquist) of sources[2].multisine"},
    {"MixEntryNaN", [](Recipe& r) { r.mix[3][2] = kNaN; }, StatusCode::invalid_field,
     "mix[3][2] = nan, expected a finite number"},
    {"LineAmplitudeInfinite", [](Recipe& r) { r.lines[70].amplitude = -kInf; },
     StatusCode::invalid_field, "lines[70].amplitude = -inf, expected a finite number"},
    {"LinePhaseTooLarge", [](Recipe& r) { r.lines[0].phase = 2e6; }, StatusCode::invalid_field,
     "lines[0].phase = 2e+06 rad, expected finite with |phase| ≤ 1e+06"},
};

INSTANTIATE_TEST_SUITE_P(EachBrokenField, ValidateRefuses, ::testing::ValuesIn(kBadFields),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

}  // namespace
}  // namespace excite::signal
