// SPDX-License-Identifier: MIT
// Identification honours the run log's flags (issue 10 §6): flagged rows are not scored but
// still drive the model, a discontinuity restarts the model, several runs are stacked, short
// segments are dropped and counted (host/identify/run_layout.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "firmware/runlog/format.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/run_layout.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

const std::vector<ElementModel> kFlaggedTruth = {
    {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
constexpr double kT = 0.5;

runlog::RunLog make_log(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y,
                        const std::vector<std::uint32_t>& flags) {
  runlog::RunLog log;
  log.sample_time_min = kT;
  log.input_names = {"L", "V"};
  log.input_units = {"kmol/min", "kmol/min"};
  log.output_names = {"xD", "xB"};
  log.output_units = {"mol/mol", "mol/mol"};
  for (Eigen::Index k = 0; k < U.rows(); ++k) {
    log.t_min.push_back(static_cast<double>(k) * kT);
    log.k.push_back(static_cast<std::uint64_t>(k));
  }
  for (Eigen::Index i = 0; i < U.cols(); ++i) {
    log.du.emplace_back(U.col(i).data(), U.col(i).data() + U.rows());
    log.u.push_back(log.du.back());
  }
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    log.dy.emplace_back(Y.col(j).data(), Y.col(j).data() + Y.rows());
  }
  log.flags = flags;
  return log;
}

StackedRuns one_run(const runlog::RunLog& log, const FlagRule& rule = {}) {
  return stack_runs({&log}, {"run.csv"}, rule);
}

IdentificationResult identify_runs(const StackedRuns& d) {
  return identify(d.U, d.Y, d.sample_time_min, d.layout);
}

// Largest relative gain error over the four elements.
double gain_error(const IdentificationResult& r) {
  double worst = 0.0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const double t = kFlaggedTruth[static_cast<std::size_t>(2 * j + i)].gain;
      worst = std::max(worst, std::abs(r.model.element(j, i).value.gain - t) / std::abs(t));
    }
  }
  return worst;
}

double worst_fit(const IdentificationResult& r) {
  return std::min(r.fits[0].fit_percent, r.fits[1].fit_percent);
}

TEST(FlaggedRows, SuspendedSpanIsNotScoredButDrivesTheModelAndUsingItIsWorse) {
  // The plant runs on; over rows 700–899 the engine is suspended (inputs held at the
  // baseline, which the plant sees) and the logged outputs are junk (a stuck transmitter).
  Eigen::MatrixXd U = testing::prbs_inputs(2, 6, 16, 31, 2016, 1.0);
  U.middleRows(700, 200).setZero();
  const Eigen::MatrixXd Y_true = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U);
  Eigen::MatrixXd Y = Y_true;
  for (Eigen::Index k = 700; k < 900; ++k) Y.row(k) = Y_true.row(699);
  std::vector<std::uint32_t> flags(2016, 0);
  for (std::size_t k = 700; k < 900; ++k) flags[k] = runlog::kSuspended;
  const runlog::RunLog log = make_log(U, Y, flags);

  const StackedRuns honoured = one_run(log);
  EXPECT_EQ(honoured.report.flagged_excluded, 200);
  EXPECT_EQ(honoured.report.rows_with_flag[0], 200);  // suspended
  EXPECT_EQ(honoured.report.scored, 2016 - 200);
  EXPECT_EQ(honoured.report.segments, 1);  // the state carries across: no restart
  const IdentificationResult good = identify_runs(honoured);
  EXPECT_LT(gain_error(good), 1e-3);
  EXPECT_GT(worst_fit(good), 99.9);

  // The same run with clean outputs over the span gives the same model.
  const runlog::RunLog clean = make_log(U, Y_true, std::vector<std::uint32_t>(2016, 0));
  const IdentificationResult reference = identify_runs(one_run(clean));
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(good.model.element(j, i).value.gain, reference.model.element(j, i).value.gain,
                  1e-3 * std::abs(reference.model.element(j, i).value.gain));
    }
  }

  FlagRule keep;
  keep.keep_flagged = true;
  const StackedRuns kept = one_run(log, keep);
  EXPECT_EQ(kept.report.flagged_excluded, 0);
  EXPECT_EQ(kept.report.rows_with_flag[0], 200);  // still counted
  const IdentificationResult bad = identify_runs(kept);
  EXPECT_LT(worst_fit(bad), 99.0);
  EXPECT_GT(gain_error(bad), 10.0 * gain_error(good));
}

TEST(FlaggedRows, DiscontinuityRestartsTheModelAndIgnoringItIsWorse) {
  // The plant restarts at row 1000 (its state back to rest), the inputs go on.
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 6, 16, 31, 2016, 1.0);
  Eigen::MatrixXd Y(2016, 2);
  Y.topRows(1000) = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U.topRows(1000));
  Y.bottomRows(1016) = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U.bottomRows(1016));
  std::vector<std::uint32_t> flags(2016, 0);
  flags[1000] = runlog::kDiscontinuity;

  const StackedRuns split = one_run(make_log(U, Y, flags));
  EXPECT_EQ(split.report.segments, 2);
  EXPECT_EQ(split.report.discontinuities, 1);
  ASSERT_EQ(split.layout.segments.size(), 2U);
  EXPECT_EQ(split.layout.segments[1].begin, 1000);
  EXPECT_EQ(split.report.warm_up, 40);  // 20 min of warm-up at T = 0.5 min
  const IdentificationResult good = identify_runs(split);
  EXPECT_LT(gain_error(good), 1e-3);
  EXPECT_GT(worst_fit(good), 99.9);

  const IdentificationResult ignored =
      identify_runs(one_run(make_log(U, Y, std::vector<std::uint32_t>(2016, 0))));
  EXPECT_LT(worst_fit(ignored), worst_fit(good) - 0.5);
}

TEST(FlaggedRows, SeveralRunsAreIdentifiedTogetherEachFromRest) {
  // A step test (both inputs stepped in turn) and a short PRBS run: neither alone shows
  // every element as well; together they give the plant back.
  Eigen::MatrixXd step = Eigen::MatrixXd::Zero(600, 2);
  step.block(10, 0, 590, 1).setConstant(1.0);
  step.block(300, 1, 300, 1).setConstant(-1.0);
  const Eigen::MatrixXd U2 = testing::prbs_inputs(2, 5, 8, 15, 500, 1.0);
  const runlog::RunLog a = make_log(step, testing::plant_outputs(kFlaggedTruth, 2, 2, kT, step),
                                    std::vector<std::uint32_t>(600, 0));
  const runlog::RunLog b = make_log(U2, testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U2),
                                    std::vector<std::uint32_t>(500, 0));
  const StackedRuns both = stack_runs({&a, &b}, {"step.csv", "prbs.csv"}, {});
  EXPECT_EQ(both.report.rows, 1100);
  EXPECT_EQ(both.report.segments, 2);
  EXPECT_EQ(both.report.warm_up, 0);  // each run starts at the operating point
  const IdentificationResult r = identify_runs(both);
  EXPECT_LT(gain_error(r), 1e-3);
  EXPECT_GT(worst_fit(r), 99.9);
}

TEST(FlaggedRows, RunsWithOtherChannelsOrSampleTimeAreRefusedByName) {
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 5, 8, 15, 200, 1.0);
  const Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(200, 2);
  const runlog::RunLog a = make_log(U, Y, std::vector<std::uint32_t>(200, 0));
  runlog::RunLog b = a;
  b.output_names = {"xD", "xS"};
  try {
    (void)stack_runs({&a, &b}, {"a.csv", "b.csv"}, {});
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("b.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("xS"), std::string::npos) << e.what();
  }
  runlog::RunLog c = a;
  c.sample_time_min = 1.0;
  EXPECT_THROW((void)stack_runs({&a, &c}, {"a.csv", "c.csv"}, {}), std::invalid_argument);
}

TEST(FlaggedRows, ShortSegmentsAreDroppedAndCounted) {
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 5, 8, 15, 400, 1.0);
  const Eigen::MatrixXd Y = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U);
  std::vector<std::uint32_t> flags(400, 0);
  flags[100] = runlog::kDiscontinuity;  // a segment of 45 rows: 40 warm-up, 5 scored
  flags[145] = runlog::kSkipped;        // then one of 255 rows
  const StackedRuns d = one_run(make_log(U, Y, flags));
  EXPECT_EQ(d.report.dropped_segments, 1);
  EXPECT_EQ(d.report.dropped_segment_rows, 5);
  EXPECT_EQ(d.report.segments, 2);
  EXPECT_EQ(d.report.skips, 1);
  EXPECT_EQ(d.report.scored, 100 + (255 - 40));
  EXPECT_EQ(d.layout.weight.segment(100, 45).sum(), 0.0);
}

TEST(FlaggedRows, CommLostSpanRestartsTheModelAfterIt) {
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 5, 8, 15, 400, 1.0);
  const Eigen::MatrixXd Y = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U);
  std::vector<std::uint32_t> flags(400, 0);
  for (std::size_t k = 200; k < 210; ++k) flags[k] = runlog::kCommLost;
  const StackedRuns d = one_run(make_log(U, Y, flags));
  ASSERT_EQ(d.layout.segments.size(), 2U);
  EXPECT_EQ(d.layout.segments[1].begin, 210);
  EXPECT_EQ(d.report.flagged_excluded, 10);
  EXPECT_EQ(d.report.warm_up, 40);
}

TEST(FittedTrend, OffsetAndDriftPerSegmentAreFittedWithTheModel) {
  // Each segment's outputs carry an offset and a drift the model cannot explain; with the
  // trend fitted (by projection) the plant comes back exactly, without it it does not.
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 6, 16, 31, 2016, 1.0);
  Eigen::MatrixXd Y(2016, 2);
  Y.topRows(1000) = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U.topRows(1000));
  Y.bottomRows(1016) = testing::plant_outputs(kFlaggedTruth, 2, 2, kT, U.bottomRows(1016));
  for (Eigen::Index k = 0; k < 2016; ++k) {
    const double t = static_cast<double>(k) * kT;
    Y(k, 0) += k < 1000 ? 0.5 + 0.002 * t : -0.3 - 0.001 * t;
    Y(k, 1) += 0.2 + 0.0005 * t;
  }
  std::vector<std::uint32_t> flags(2016, 0);
  flags[1000] = runlog::kDiscontinuity;
  const StackedRuns d = one_run(make_log(U, Y, flags));
  IdentifyOptions with_trend;
  with_trend.trend = Trend::linear;
  const IdentificationResult fitted = identify(d.U, d.Y, d.sample_time_min, d.layout, with_trend);
  EXPECT_LT(gain_error(fitted), 1e-3);
  EXPECT_GT(worst_fit(fitted), 99.9);
  const IdentificationResult ignored = identify_runs(d);
  EXPECT_GT(gain_error(ignored), 0.05);
  EXPECT_EQ(trend_basis(d.layout, Trend::linear).cols(), 4);  // two segments × (offset, slope)
  EXPECT_EQ(trend_basis(d.layout, Trend::none).cols(), 0);
}

TEST(SegmentMeans, ScoredRowsOfEachSegmentArePooledAboutThatSegmentsMean) {
  // Two segments at different operating points (the second offset by 10), row 1 not scored,
  // segment [4, 5) with no scored row.
  SampleLayout layout;
  layout.segments = {{0, 4}, {4, 5}, {5, 8}};
  layout.weight = Eigen::VectorXd::Ones(8);
  layout.weight(1) = 0.0;
  layout.weight(4) = 0.0;
  layout.check();
  Eigen::MatrixXd Y(8, 2);
  Y << 1, -1, 99, 99, 2, -2, 3, -3, 99, 99, 10, 20, 12, 22, 14, 24;
  const Eigen::MatrixXd rows = layout.scored_rows(Y, 0, 5);
  ASSERT_EQ(rows.rows(), 3);
  EXPECT_EQ(rows(2, 1), -3.0);
  const Eigen::MatrixXd pooled = scored_about_segment_means(Y, layout);
  Eigen::MatrixXd expected(6, 2);
  expected << -1, 1, 0, 0, 1, -1, -2, -2, 0, 0, 2, 2;
  EXPECT_TRUE(pooled.isApprox(expected)) << pooled;
}

}  // namespace
}  // namespace excite::host
