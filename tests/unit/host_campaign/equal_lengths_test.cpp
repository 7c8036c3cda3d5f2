// SPDX-License-Identifier: MIT
// The campaign compares designs at equal cost (issue 23 §1, SPEC §4, thesis §6.3: "T_L =
// 4080 min was the same for all cases"): unequal lengths are refused naming every length,
// unless allowed, and then said.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "host/campaign/campaign.hpp"

namespace excite::host {
namespace {

TEST(CheckEqualLengths, RefusesUnequalLengthsNamingEveryOne) {
  const std::vector<std::pair<std::string, Eigen::Index>> lengths{
      {"stepSeq", 4080}, {"msGlmSeq", 15080}, {"msGlmZipm", 4713}};
  try {
    check_equal_lengths(lengths, false, {});
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stepSeq 4080, msGlmSeq 15080, msGlmZipm 4713 samples"), std::string::npos)
        << what;
    EXPECT_NE(what.find("--allow-unequal-length"), std::string::npos) << what;
  }
  std::string said;
  EXPECT_NO_THROW(check_equal_lengths(lengths, true, [&](const std::string& s) { said += s; }));
  EXPECT_NE(said.find("msGlmSeq 15080"), std::string::npos) << said;
}

TEST(CheckEqualLengths, EqualLengthsPassSilently) {
  std::string said;
  check_equal_lengths({{"a", 4080}, {"b", 4080}}, false, [&](const std::string& s) { said += s; });
  EXPECT_EQ(said, "");
}

}  // namespace
}  // namespace excite::host
