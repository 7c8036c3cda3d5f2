// SPDX-License-Identifier: MIT
#include "host/design/prbs_a1.hpp"

#include <gtest/gtest.h>

#include "host/design/case_studies.hpp"

namespace excite::host {
namespace {

// SPEC §4: τ_H = 50, τ_L = 12, α = 2, β = 3, T = 1 min, n = 4 inputs.
TEST(DesignProcedureA1, ArrivesAtTheCaseStudyDesign) {
  const PrbsDesign d = design_prbs(case_study("alatiqi4x4"));
  EXPECT_DOUBLE_EQ(d.switch_time_min, 16.0);  // 2.8·12/2 = 16.8 → 16
  EXPECT_EQ(d.hold_samples, 16U);
  EXPECT_DOUBLE_EQ(d.shift_intervals, 15.625);  // 5·50/16, not rounded
  EXPECT_EQ(d.register_length, 6);              // N_s ≥ max(58.9, 62.5) → 63
  EXPECT_EQ(d.period_bits, 63U);
  EXPECT_EQ(d.long_register_length, 8);    // 4·63 = 252 ≤ 255
  EXPECT_EQ(d.experiment_samples, 4080U);  // 255·16, the thesis's 4080 min
}

TEST(DesignProcedureA1, ExplainsEveryInequalityWithItsNumbers) {
  const PrbsDesign d = design_prbs(case_study("alatiqi4x4"));
  ASSERT_GE(d.explanation.size(), 4U);
  EXPECT_NE(d.explanation[0].find("16.800"), std::string::npos) << d.explanation[0];
  EXPECT_NE(d.explanation[2].find("62.50"), std::string::npos) << d.explanation[2];
}

TEST(DesignProcedureA1, RefusesASwitchingTimeShorterThanASample) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.sample_time_min = 20.0;
  try {
    design_prbs(prior);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4.2.3"), std::string::npos) << e.what();
  }
}

TEST(ChannelShift, IsCeilingOfDWhenAllCopiesFit) {
  EXPECT_EQ(channel_shift(15.625, 255, 4), 16U);  // 4·16 = 64 ≤ 255
}

TEST(ChannelShift, FallsBackToMaximalEqualSpacing) {
  EXPECT_EQ(channel_shift(15.625, 63, 4), 15U);  // 4·16 = 64 > 63 → ⌊63/4⌋
}

TEST(PriorKnowledge, RefusesNonPositiveTimeConstantsNamingTheField) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.tau_low_min = -1.0;
  try {
    validate(prior);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tau_low_min = -1"), std::string::npos) << e.what();
  }
}

TEST(PriorKnowledge, RefusesAnAmplitudeBeyondTheLimits) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.inputs[2].amplitude = 20.0;  // the case study's limits are ±15
  try {
    validate(prior);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inputs[2].amplitude = 20"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace excite::host
