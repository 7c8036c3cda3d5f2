// SPDX-License-Identifier: MIT
// The upper bound of the identified time constants (host/design/time_constant_bound.hpp): the
// order in which the sources are taken, the widest of several run logs, and the refusal that
// names the options.

#include "host/design/time_constant_bound.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "host/design/case_studies.hpp"

namespace excite::host {
namespace {

TEST(TimeConstantBound, AnExplicitBoundWinsAndZeroMeansTheRunsLength) {
  TimeConstantBoundOptions o;
  o.max_time_constant_min = 120.0;
  o.tau_high_min = 50.0;
  const auto [bound, source] = time_constant_bound(o, {{"a.csv", "alatiqi4x4", 30.0, 2.0}});
  EXPECT_EQ(bound, 120.0);
  EXPECT_EQ(source, "--max-time-constant");
  o.max_time_constant_min = 0.0;
  EXPECT_EQ(time_constant_bound(o, {}).first, 0.0);
}

TEST(TimeConstantBound, TauHighTakesTheGivenBetaElseTheFirstLogsElseThree) {
  TimeConstantBoundOptions o;
  o.tau_high_min = 50.0;
  EXPECT_EQ(time_constant_bound(o, {}).first, 150.0);
  EXPECT_EQ(time_constant_bound(o, {{"a.csv", "p", 0.0, 2.0}}).first, 100.0);
  o.beta = 4.0;
  const auto [bound, source] = time_constant_bound(o, {{"a.csv", "p", 0.0, 2.0}});
  EXPECT_EQ(bound, 200.0);
  EXPECT_EQ(source, "beta 4 x --tau-high");
}

TEST(TimeConstantBound, TheWidestRunLogHeaderWinsOverTheCaseStudy) {
  const auto [bound, source] = time_constant_bound(
      {}, {{"short.csv", "alatiqi4x4", 20.0, 3.0}, {"long.csv", "alatiqi4x4", 30.0, 0.0}});
  EXPECT_EQ(bound, 90.0);  // the second log's β is absent: 3
  EXPECT_EQ(source, "beta x tau_H of the run log long.csv, beta = 3, tau_H = 30 min");
}

TEST(TimeConstantBound, ALogWithoutTimeScalesTakesItsPlantsCaseStudy) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const auto [bound, source] = time_constant_bound({}, {{"old.csv", "alatiqi4x4", 0.0, 0.0}});
  EXPECT_EQ(bound, prior.beta * prior.tau_high_min);
  EXPECT_NE(source.find("alatiqi4x4 case study"), std::string::npos) << source;
}

TEST(TimeConstantBound, NoSourceIsRefusedNamingTheOptions) {
  try {
    time_constant_bound({}, {{"x.csv", "my_column", 0.0, 0.0}});
    FAIL() << "no bound is known, expected a refusal";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("x.csv: tau_high_min = "), std::string::npos) << what;
    EXPECT_NE(what.find("\"my_column\" has no case study"), std::string::npos) << what;
    EXPECT_NE(what.find("--tau-high MIN"), std::string::npos) << what;
    EXPECT_NE(what.find("--max-time-constant 0"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace excite::host
