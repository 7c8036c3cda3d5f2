// SPDX-License-Identifier: MIT
// The adaptive test measured over 100 noise seeds against the truth it never sees (issue 26
// §2, §4; host/adaptive/README.md has the tables these bounds come from):
//  - the stop rule is honest: it claims 95 % (its intervals inside the criterion's
//    tolerances), so of 100 seeds at most 9 may stop with a model that misses the criterion
//    (9: the 95 % upper bound of a binomial count of 100 draws at 5 %);
//  - it stops early: 90 % of seeds have stopped with a good model by a quarter of the plain
//    design it starts from (alatiqi4x4: 1020 of 4080 min);
//  - with CV test limits, no seed's noise-free CVs leave them, while every fixed design of
//    the comparison at its designed amplitude does.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "host/adaptive/decision_log.hpp"
#include "host/adaptive/study.hpp"
#include "host/design/case_studies.hpp"

namespace excite::host {
namespace {

constexpr int kSeeds = 100;
constexpr int kMostWrongStops = 9;

struct Tally {
  int stopped = 0, wrong = 0, violated = 0;
};

Tally tally(const StudyResult& s) {
  Tally t;
  for (const SeedOutcome& x : s.seeds) {
    if (x.stopped_by_rule) ++t.stopped;
    if (x.stopped_by_rule && !x.met_at_stop) ++t.wrong;
    if (x.violated) ++t.violated;
  }
  return t;
}

StudyResult study(const std::string& plant, const AdaptiveOptions& adaptive) {
  StudyOptions o;
  o.plant = plant;
  o.seeds = kSeeds;
  o.threads = 2;
  o.adaptive = adaptive;
  StudyResult s = run_study(o);
  std::printf("%s", study_text(s).c_str());
  return s;
}

TEST(AdaptiveStudy, AlatiqiStopsHonestlyAndEarly) {
  const StudyResult s = study("alatiqi4x4", AdaptiveOptions{});
  const Tally t = tally(s);
  EXPECT_GE(t.stopped, 95);
  EXPECT_LE(t.wrong, kMostWrongStops);
  ASSERT_TRUE(s.t90_stop.has_value());
  EXPECT_LE(s.grid_min[*s.t90_stop], 4080.0 / 4.0);
}

TEST(AdaptiveStudy, WoodBerryStopsHonestly) {
  const StudyResult s = study("woodberry2x2", AdaptiveOptions{});
  const Tally t = tally(s);
  EXPECT_GE(t.stopped, 95);
  EXPECT_LE(t.wrong, kMostWrongStops);
  EXPECT_TRUE(s.t90_stop.has_value());
}

TEST(AdaptiveStudy, ColaAStopsHonestlyThoughItsResidualsAreNeverWhite) {
  // The nonlinear column open loop (host/adaptive/README.md, "colaA"): a linear model leaves a
  // residual that is never white and depends on no input. When every such row restarted
  // every element on any lower BIC (d23bea5 … 4eef0a4), 90 seeds stopped at 2 331 min, 13
  // wrong, and 90 % never stopped with a good model; with the restart kept only beyond the
  // residual's colour (structure_search.cpp) T90 is 3 885 min again, 6 wrong.
  const StudyResult s = study("colaA", AdaptiveOptions{});
  const Tally t = tally(s);
  EXPECT_LE(t.wrong, kMostWrongStops);
  ASSERT_TRUE(s.t90_stop.has_value());
  EXPECT_LE(s.grid_min[*s.t90_stop], 3885.0);
}

TEST(AdaptiveStudy, AlatiqiKeepsTheLimitsTheFixedDesignsLeave) {
  AdaptiveOptions a;
  a.first_scale = 0.5;
  a.limits = CvLimits{Eigen::VectorXd::Constant(4, -1.0), Eigen::VectorXd::Constant(4, 1.0)};
  const StudyResult s = study("alatiqi4x4", a);
  const Tally t = tally(s);
  EXPECT_EQ(t.violated, 0);
  EXPECT_LE(t.wrong, kMostWrongStops);
  EXPECT_TRUE(s.t90_stop.has_value());
  // The fixed designs at their designed amplitude on the same (nominal) plant.
  for (const char* design : {"prbsUnc", "prbsSimDir", "prbsDirCorrSim", "msGlmZipm"}) {
    EXPECT_GT(fixed_design_peak_ratio("alatiqi4x4", design, *a.limits, 0.0, 1), 1.0) << design;
  }
}

TEST(AdaptiveStudy, AlatiqiUnderItsDmcStopsHonestlyInsideTheCvLimits) {
  // The controller on (issue 41 §4): each segment's r on the CV setpoints of the example DMC
  // (its model the plant's own), at half of the file's CV test limits ±0.55, r cut to the MVs'
  // room (±0.6), the direct estimate with its noise model. Measured: 100 of 100 stopped, 0
  // wrong, no CV outside its limits (noise-free peak 0.77 of them), T90 1 248 min at 58dfea8
  // (1 040 min and a peak of 0.83 when first measured, before stop 55's identifier).
  StudyOptions o;
  o.plant = "alatiqi4x4";
  o.seeds = kSeeds;
  o.threads = 2;
  o.adaptive.limits =
      CvLimits{Eigen::VectorXd::Constant(4, -0.55), Eigen::VectorXd::Constant(4, 0.55)};
  o.closed_loop = ClosedLoopStudyOptions{};
  o.closed_loop->controller = std::string(EXCITE_CONTROL_EXAMPLES) + "/alatiqi4x4.dmc.toml";
  const StudyResult s = run_study(o);
  std::printf("%s", study_text(s).c_str());
  const Tally t = tally(s);
  EXPECT_EQ(s.not_run, 0);
  EXPECT_GE(t.stopped, 95);
  EXPECT_LE(t.wrong, kMostWrongStops);
  EXPECT_EQ(t.violated, 0);
  ASSERT_TRUE(s.t90_stop.has_value());
  EXPECT_LE(s.grid_min[*s.t90_stop], 4080.0 / 3.0);
}

}  // namespace
}  // namespace excite::host
