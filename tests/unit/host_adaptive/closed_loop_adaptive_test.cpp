// SPDX-License-Identifier: MIT
// The adaptive test with the controller on (host/adaptive/closed_loop_adaptive.hpp): the loop
// that continues one record, the re-aimed segments, the stop, the refusals.
#include "host/adaptive/closed_loop_adaptive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "host/adaptive/segments.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/design/case_studies.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/measures/accuracy.hpp"
#include "host/measures/gain_directions.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"

namespace excite::host {
namespace {

struct WoodBerryUnderPi {
  PriorKnowledge prior = case_study("woodberry2x2");
  std::unique_ptr<sim::Plant> plant = sim::make_plant("woodberry2x2");
  sim::control::ControllerFile file = sim::control::load_controller_file(
      std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml");
  std::unique_ptr<sim::control::Controller> controller;
  std::unique_ptr<ClosedLoopPlant> loop;

  // `disturbance_std` > 0: the coloured output disturbance too, τ 20 min.
  explicit WoodBerryUnderPi(std::uint64_t seed, double disturbance_std = 0.0) {
    const Eigen::MatrixXd g0 = plant->static_gain();
    controller = sim::control::make_controller(file, *sim::control::load_model(file), &g0);
    ClosedLoopOptions options;
    set_controller(options, file, "woodberry2x2.pi.toml");
    SimulationOptions noise;
    noise.seed = seed;
    noise.noise_variance = 1e-2;
    noise.disturbance_std = disturbance_std;
    noise.disturbance_tau_min = 20.0;
    loop = std::make_unique<ClosedLoopPlant>(*plant, *controller, options, noise,
                                             prior.sample_time_min);
  }
};

ClosedLoopAdaptiveOptions limits_of_2() {
  ClosedLoopAdaptiveOptions o;
  o.adaptive.limits = CvLimits{Eigen::Vector2d(-2.0, -2.0), Eigen::Vector2d(2.0, 2.0)};
  return o;
}

TEST(ClosedLoopAdaptive, ALongerRecordContinuesTheShorterOneExactly) {
  // The test simulates its whole r record again after each segment: its noise is drawn row
  // by row from the seed, so the rows already measured come out the same.
  WoodBerryUnderPi w(5);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(300, 2);
  r.block(10, 0, 290, 1).setConstant(1.0);
  r.block(150, 1, 150, 1).setConstant(-0.5);
  const SimulatedRun longer = w.loop->run(r);
  const SimulatedRun shorter = w.loop->run(r.topRows(200));
  EXPECT_EQ(longer.dy.topRows(200), shorter.dy);
  EXPECT_EQ(longer.du.topRows(200), shorter.du);
  // Noise-free: the same r without the noise.
  EXPECT_NE(w.loop->run(r, true).dy, longer.dy);
}

TEST(ClosedLoopAdaptive, WoodBerryUnderPiStopsByTheRuleAfterReAimedSegments) {
  WoodBerryUnderPi w(1);
  const AdaptiveResult r = run_closed_loop_adaptive_test(w.prior, *w.loop, limits_of_2());
  EXPECT_TRUE(r.criterion_met) << r.stop_reason;
  ASSERT_GE(r.segments.size(), 3U);  // the rule needs an estimate a settling time earlier
  EXPECT_FALSE(r.segments[0].directional);
  EXPECT_TRUE(r.segments.back().directional) << r.segments.back().why;
  // Every row measured and simulated noise-free; the CVs held inside their limits (r at half).
  EXPECT_EQ(r.U.rows(), r.Y.rows());
  EXPECT_EQ(r.Y_true.rows(), r.Y.rows());
  ASSERT_EQ(r.rows_outside_limits.size(), 2U);
  EXPECT_LT(r.Y_true.cwiseAbs().maxCoeff(), 2.0);
  // The stopping estimate meets the accuracy criterion against the truth.
  const TruePlant truth = true_plant_of(w.plant->static_gain());
  EXPECT_TRUE(judge(truth, r.estimates.back().result.gain).met);
}

TEST(ClosedLoopAdaptive, TheTwoStageEstimatesTheRuleReadsAreFinishedByTheInstrumentStep) {
  // GIVEN the two-stage estimate under a coloured disturbance, its gains and SEs from the
  // instrumental-variable step (host/identify/two_stage_uncertainty.hpp).
  WoodBerryUnderPi w(1, 0.3);
  ClosedLoopAdaptiveOptions o = limits_of_2();
  o.two_stage = true;
  const AdaptiveResult r = run_closed_loop_adaptive_test(w.prior, *w.loop, o);
  ASSERT_FALSE(r.estimates.empty()) << r.stop_reason;
  // WHEN the last estimate's rows are identified two-stage again, with the test's options.
  const Reestimate& last = r.estimates.back();
  const auto rows = static_cast<Eigen::Index>(last.samples);
  IdentifyOptions options = o.adaptive.identify;
  options.max_time_constant_min = w.prior.beta * w.prior.tau_high_min;
  const TwoStageFit again =
      identify_two_stage(r.U.topRows(rows), r.R.topRows(rows), r.Y.topRows(rows), r.sample_time_min,
                         SampleLayout::whole(rows), options);
  // THEN the SEs the rule read are those after the instrumental-variable step, not stage 2's
  // own.
  EXPECT_GT((again.stage1_se_factor.array() - 1.0).abs().maxCoeff(), 0.01);
  ASSERT_TRUE(last.uncertainty.has_value());
  ASSERT_TRUE(again.fit.result.gain_uncertainty.has_value());
  EXPECT_EQ(last.uncertainty->singular_value_se,
            again.fit.result.gain_uncertainty->singular_value_se);
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(last.result.model.element(i, j).std_error.gain,
                again.fit.result.model.element(i, j).std_error.gain);
    }
  }
}

TEST(ClosedLoopAdaptive, TheFirstSegmentAlongThePriorsOutputDirectionsPutsEachSourceOnOne) {
  // One segment, plain and along the prior's W. Wood-Berry's W is a rotation, so both rows of
  // W have the same absolute sum and r = a·c·W s: Wᵀr takes two values per column (±a·c),
  // where plain r = a·s gives Wᵀr four (every sign pattern of s on each row of Wᵀ).
  const auto first_segment = [](bool prior_directions) {
    WoodBerryUnderPi w(1);
    ClosedLoopAdaptiveOptions o = limits_of_2();
    o.prior_directions = prior_directions;
    o.adaptive.segment_min = 1e6;     // one segment, the prior's whole prbsUnc length: every
    o.adaptive.max_length_min = 0.0;  // sign pattern of the sources occurs
    AdaptiveResult r = run_closed_loop_adaptive_test(w.prior, *w.loop, o);
    EXPECT_EQ(r.R.rows(), r.U.rows());
    r.R = r.R.topRows(r.segments[0].rows).eval();  // the first segment's r
    return std::make_pair(r, analyse_gain(w.prior.gain).output_directions);
  };
  const auto distinct = [](const Eigen::VectorXd& x) {
    std::vector<double> v;
    for (const double value : x) {
      if (std::none_of(v.begin(), v.end(), [&](double seen) {
            return std::abs(seen - value) <= 1e-9 * x.cwiseAbs().maxCoeff();
          })) {
        v.push_back(value);
      }
    }
    return v.size();
  };
  const auto [along, W] = first_segment(true);
  EXPECT_TRUE(along.segments[0].directional);
  EXPECT_EQ(along.segments[0].from_estimate, -1);
  EXPECT_NE(along.segments[0].why.find("prior's output directions"), std::string::npos)
      << along.segments[0].why;
  const Eigen::MatrixXd s_along = along.R * W;  // rows × directions: Wᵀr per row
  for (Eigen::Index i = 0; i < 2; ++i) EXPECT_EQ(distinct(s_along.col(i)), 2U) << "direction " << i;
  // Each CV's peak |r_j| is its amplitude, half of ±2 (times the MVs' room's scale).
  for (Eigen::Index j = 0; j < 2; ++j) {
    EXPECT_NEAR(along.R.col(j).cwiseAbs().maxCoeff(), along.segments[0].scale, 1e-12);
  }

  const auto [plain, W_plain] = first_segment(false);
  EXPECT_FALSE(plain.segments[0].directional);
  const Eigen::MatrixXd s_plain = plain.R * W_plain;
  for (Eigen::Index i = 0; i < 2; ++i) EXPECT_EQ(distinct(s_plain.col(i)), 4U) << "direction " << i;
}

TEST(ClosedLoopAdaptive, APrbsPhaseStartsTheSourcesThatManySwitchingIntervalsIn) {
  // One plain segment each, not cut for the MVs' room (so r is a·s exactly): from phase 0
  // over 600 rows, and from phase 5 over 300.
  const auto first_segment = [](std::uint64_t phase, double rows) {
    WoodBerryUnderPi w(1);
    ClosedLoopAdaptiveOptions o = limits_of_2();
    o.mv_fraction = 0.0;
    o.prbs_phase = phase;
    o.adaptive.segment_min = rows;
    o.adaptive.max_length_min = rows;
    return run_closed_loop_adaptive_test(w.prior, *w.loop, o).R;
  };
  const std::uint32_t hold =
      segment_sources(case_study("woodberry2x2")).plain.plan->recipe.sources[0].prbs.hold_samples;
  const Eigen::MatrixXd from_0 = first_segment(0, 600.0);
  const Eigen::MatrixXd from_5 = first_segment(5, 300.0);
  ASSERT_GE(from_0.rows(), 5 * hold + from_5.rows());
  EXPECT_EQ(from_5, from_0.middleRows(5 * hold, from_5.rows()));
  EXPECT_NE(from_5, from_0.topRows(from_5.rows()));
}

TEST(ClosedLoopAdaptive, ThePisLoopFollowsWoodBerrysWeakDirectionSlowerThanItsStrongOne) {
  // at_the_loops_pace times a switch along the prior's weakest output direction, the
  // controller on its own model; the same switch's size along the strongest direction is
  // followed faster. The weak direction's loop outlasts the plant's τ_H, so τ_L stops there.
  WoodBerryUnderPi w(1);
  const LoopPace pace = at_the_loops_pace(w.prior, Eigen::Vector2d(1.0, 1.0), 1.0, w.file);
  auto model = sim::control::load_model(w.file);
  ClosedLoopOptions loop;
  set_controller(loop, w.file, "woodberry2x2.pi.toml");
  const Eigen::MatrixXd W = analyse_gain(w.prior.gain).output_directions;
  const ClosedLoopSpeed strong =
      closed_loop_speed(0.1 * W.col(0), 200, 1.0, *model, *w.controller, loop);
  ASSERT_TRUE(pace.speed.reached);
  ASSERT_TRUE(strong.reached);
  EXPECT_GT(pace.speed.time_constant_min, 2.0 * strong.time_constant_min);
  ASSERT_GT(pace.speed.time_constant_min, w.prior.tau_high_min);
  EXPECT_EQ(pace.prior.tau_low_min, w.prior.tau_high_min);
  EXPECT_EQ(pace.prior.tau_high_min, w.prior.tau_high_min);  // only τ_L moves
}

TEST(ClosedLoopAdaptive, AStudysSetpointDesignsTakeTheLoopsPaceOnlyWhenToldAndForSetpoints) {
  // setpoint_pace: the campaign's and the Monte Carlo study's designs. CV limits −2:2 and
  // −3:2 at half give amplitudes 1 (the nearer limit), as above; "plant" and an MV dither
  // keep the prior's τ_L.
  WoodBerryUnderPi w(1);
  ClosedLoopDesignOptions o;
  o.cv_low = Eigen::Vector2d(-2.0, -3.0);
  o.cv_high = Eigen::Vector2d(2.0, 2.0);
  o.limit_fraction = 0.5;
  o.mv_fraction = 1.0;
  EXPECT_EQ(cv_amplitude(o.cv_low, o.cv_high, o.limit_fraction), Eigen::Vector2d(1.0, 1.0));
  const std::optional<LoopPace> pace = setpoint_pace(o, w.prior, w.file);
  ASSERT_TRUE(pace);
  const LoopPace direct = at_the_loops_pace(w.prior, Eigen::Vector2d(1.0, 1.0), 1.0, w.file);
  EXPECT_EQ(pace->speed.time_constant_min, direct.speed.time_constant_min);
  EXPECT_EQ(pace->prior.tau_low_min, direct.prior.tau_low_min);
  o.switching = "plant";
  EXPECT_FALSE(setpoint_pace(o, w.prior, w.file));
  o.switching = "loop";
  o.excitation = "mv";
  EXPECT_FALSE(setpoint_pace(o, w.prior, w.file));
  o.switching = "open";
  try {
    (void)setpoint_pace(o, w.prior, w.file);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "--switching = open, expected loop or plant");
  }
}

TEST(ClosedLoopAdaptive, OptionsAreRefusedByName) {
  WoodBerryUnderPi w(1);
  ClosedLoopAdaptiveOptions none;
  try {
    run_closed_loop_adaptive_test(w.prior, *w.loop, none);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "CV limits = none for a 2x2 plant, expected one per CV of a square plant (r is "
              "sized by them)");
  }
  ClosedLoopAdaptiveOptions o = limits_of_2();
  o.limit_fraction = 1.5;
  EXPECT_THROW(run_closed_loop_adaptive_test(w.prior, *w.loop, o), std::invalid_argument);
  o = limits_of_2();
  o.adaptive.limits->high(1) = -1.0;
  try {
    run_closed_loop_adaptive_test(w.prior, *w.loop, o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "CV 2 limits = -2:-1, expected LOW < 0 < HIGH");
  }
}

}  // namespace
}  // namespace excite::host
