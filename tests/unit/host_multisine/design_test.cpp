// SPDX-License-Identifier: MIT
#include "host/multisine/design.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace excite::host::multisine {
namespace {

// 4×4 case study (SPEC §4): T = 1 min, τ_H = 50 min, τ_L = 12 min, α = 2, β = 3.
DesignRequest case_study() {
  DesignRequest request;
  request.tau_low = 12.0;
  request.tau_high = 50.0;
  request.alpha = 2.0;
  request.beta = 3.0;
  request.channels = 4;
  request.sample_time = 1.0;
  return request;
}

std::string failure_of(const DesignRequest& request, bool zippered) {
  try {
    if (zippered) {
      design_zippered(request);
    } else {
      design_standard(request);
    }
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no exception";
}

bool mentions(const std::vector<std::string>& lines, const std::string& text) {
  for (const auto& line : lines) {
    if (line.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(DesignA2, CaseStudyGivesTheSmallestPeriodAndLineCount) {
  // 4.4.27: N_s ≥ 2π/(T ω_L) = 2π·150 = 942.48 → 943; 4.4.28: n_s ≥ 943/(6·2π) = 25.01 → 26.
  const auto design = design_standard(case_study());
  EXPECT_DOUBLE_EQ(design.omega_low, 1.0 / 150.0);
  EXPECT_DOUBLE_EQ(design.omega_high, 1.0 / 6.0);
  EXPECT_EQ(design.period, 943U);
  EXPECT_EQ(design.lines, 26U);
  EXPECT_TRUE(mentions(design.explanation, "4.4.27"));
  EXPECT_TRUE(mentions(design.explanation, "4.4.28"));
}

TEST(DesignA3, CaseStudyZipperedGivesTheSmallestPeriodAndLineCount) {
  // 4.4.30: N_s ≥ 2π·4·150 = 3769.9 → 3770; 4.4.31: n_s ≥ 3770/(6·2π·4) = 25.0006 → 26.
  const auto design = design_zippered(case_study());
  EXPECT_EQ(design.period, 3770U);
  EXPECT_EQ(design.lines, 26U);
  EXPECT_EQ(design.slots, 4U);
}

TEST(DesignA3, ExplainsEveryConsistencyInequalityWithItsNumbers) {
  const auto design = design_zippered(case_study());
  for (const char* equation :
       {"4.4.14 (lower)", "4.4.14 (upper)", "4.4.15", "4.4.16 (lower)", "4.4.16 (upper)",
        "4.4.17 (lower)", "4.4.17 (upper)", "4.4.25", "4.4.29", "4.4.30", "4.4.31"}) {
    EXPECT_TRUE(mentions(design.explanation, equation)) << equation;
  }
  EXPECT_TRUE(mentions(design.explanation, "3770 <= 3920.71  holds"));  // 4.4.16 upper
}

TEST(DesignA3, ModifiedZipperedCountsTheSharedSlot) {
  // n + q = 5 slots: N_s ≥ 5·942.48 = 4712.4 → 4713; n_s ≥ 4713/(6·2π·5) = 25.003 → 26.
  auto request = case_study();
  request.shared_slots = 1;
  const auto design = design_zippered(request);
  EXPECT_EQ(design.period, 4713U);
  EXPECT_EQ(design.lines, 26U);
  EXPECT_EQ(design.slots, 5U);
}

TEST(DesignA3, NotchMultipliesThePeriod) {
  auto request = case_study();
  request.delta = 1;  // 4.4.30: N_s ≥ 2π·4·2·150 = 7539.8
  EXPECT_EQ(design_zippered(request).period, 7540U);
}

TEST(DesignA2, ChoosesTheSampleTimeWhenNoneIsGiven) {
  auto request = case_study();
  request.sample_time = 0.0;
  EXPECT_DOUBLE_EQ(design_standard(request).sample_time, 0.6 * 6.0);
}

TEST(DesignA3, RejectsASampleTimeWithTheBandBeyondNyquist) {
  auto request = case_study();
  request.sample_time = 20.0;  // π/ω_H = 18.85 min
  const auto message = failure_of(request, true);
  EXPECT_NE(message.find("inequality 4.4.29 fails"), std::string::npos) << message;
  EXPECT_NE(message.find("18.8496"), std::string::npos) << message;
  EXPECT_NE(message.find("off by 1.15"), std::string::npos) << message;
}

TEST(DesignA2, RejectsASampleTimeWithTheBandBeyondNyquist) {
  auto request = case_study();
  request.sample_time = 19.0;
  const auto message = failure_of(request, false);
  EXPECT_NE(message.find("inequality 4.4.26 fails"), std::string::npos) << message;
}

TEST(DesignA3, RejectsAPeriodLongerThanTheCapacity) {
  auto request = case_study();
  request.max_period = 2048;
  const auto message = failure_of(request, true);
  EXPECT_NE(message.find("capacity"), std::string::npos) << message;
  EXPECT_NE(message.find("max_period"), std::string::npos) << message;
  EXPECT_NE(message.find("3770"), std::string::npos) << message;
}

TEST(DesignA2, RejectsAnEmptyBand) {
  auto request = case_study();
  request.alpha = 0.01;  // ω_H = 0.00083 < ω_L = 0.0067
  const auto message = failure_of(request, false);
  EXPECT_NE(message.find("4.4.10"), std::string::npos) << message;
}

TEST(DesignA2, RejectsANonPositiveTimeConstantNamingTheField) {
  auto request = case_study();
  request.tau_low = 0.0;
  const auto message = failure_of(request, false);
  EXPECT_NE(message.find("tau_low"), std::string::npos) << message;
}

}  // namespace
}  // namespace excite::host::multisine
