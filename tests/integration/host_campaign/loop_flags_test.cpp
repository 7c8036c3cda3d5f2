// SPDX-License-Identifier: MIT
// `excite campaign --loop` honours the gateway's run-log flags as identify does (issue 23
// §4): the gateway's log becomes the campaign's measured data through measured_data() (what
// measured_runs_in_the_loop hands run_campaign), and the experiment identifies on the rows
// the flags rule scores (host/identify/run_layout.hpp). The logs here are the gateway's
// format, written and read back, with the flags a gateway writes when the field bus drops
// out (comm_lost: dy repeats the last good value) or the plant restarts (discontinuity).

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "firmware/runlog/format.hpp"
#include "firmware/runlog/reader.hpp"
#include "host/campaign/campaign.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/identify/validate.hpp"
#include "host/loop/campaign_runs.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPlant = "woodberry2x2";
constexpr const char* kPreset = "prbsUnc";

class LoopFlags : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("excite_loop_flags_" + std::to_string(getpid()));
    fs::create_directories(dir_);
    prior_ = case_study(kPlant);
    design_ = design_preset(prior_, find_preset(kPreset), 0);
    truth_ = analyse_gain(prior_.gain);
    SimulationOptions sim;
    sim.noise_variance = case_study_noise_variance(kPlant);
    sim.seed = 7;
    const SimulatedRun run = simulate_plan(*design_.plan, kPreset, *sim::make_plant(kPlant), sim);
    write_run_log(run, dir_ / "run.csv");
    const runlog::ReadResult read = runlog::read_run_log((dir_ / "run.csv").string());
    ASSERT_TRUE(read.ok()) << read.error->to_string();
    log_ = read.log;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The experiment as the loop campaign runs it on `log` (the gateway's log).
  Experiment experiment_on(const runlog::RunLog& log) const {
    CampaignOptions options;
    options.plant = kPlant;
    options.measured_run = [&log](const RunRequest&) { return measured_data(log, "run.csv"); };
    return run_experiment(design_, find_preset(kPreset), options, case_study_noise_variance(kPlant),
                          truth_, prior_.beta * prior_.tau_high_min);
  }

  fs::path dir_;
  PriorKnowledge prior_;
  Design design_;
  GainAnalysis truth_;
  runlog::RunLog log_;
};

// Rows [first, first + count) flagged comm_lost, their dy the last good row's (what the
// gateway logs while the field bus is down).
void lose_communication(runlog::RunLog& log, std::size_t first, std::size_t count) {
  for (std::size_t r = first; r < first + count; ++r) {
    log.flags[r] |= runlog::kCommLost;
    for (auto& column : log.dy) column[r] = column[first - 1];
  }
}

double largest_relative_gain_error(const Experiment& e, const GainAnalysis& truth) {
  double worst = 0.0;
  for (int j = 0; j < e.identified.model.outputs; ++j) {
    for (int i = 0; i < e.identified.model.inputs; ++i) {
      const double k = truth.gain(j, i);
      worst =
          std::max(worst, std::abs(e.identified.model.element(j, i).value.gain - k) / std::abs(k));
    }
  }
  return worst;
}

TEST_F(LoopFlags, RowsFlaggedCommLostAreNotScored) {
  // GIVEN the gateway's log with a field-bus drop-out of 200 rows (frozen outputs)
  const Experiment clean = experiment_on(log_);
  runlog::RunLog dropped = log_;
  const std::size_t first = 300, count = 200;
  ASSERT_GT(dropped.rows(), first + count + 100);
  lose_communication(dropped, first, count);

  // WHEN the campaign runs the experiment on it
  const Experiment e = experiment_on(dropped);

  // THEN the frozen rows and the warm-up after them are not scored: two segments, the
  // second from the first row after the drop-out
  ASSERT_EQ(e.layout.segments.size(), 2U) << "segments of the layout, expected 2: the run's "
                                             "start and the first row after the comm_lost span";
  EXPECT_EQ(e.layout.segments[1].begin, static_cast<Eigen::Index>(first + count));
  for (std::size_t r = first; r < first + count; ++r) {
    ASSERT_EQ(e.layout.weight(static_cast<Eigen::Index>(r)), 0.0)
        << "row " << r << " is flagged comm_lost, expected weight 0 (not scored)";
  }
  EXPECT_EQ(clean.layout.scored(), clean.layout.rows()) << "an unflagged log scores every row";
  // … and the model is as good as on the whole unflagged log: its own fit within 2 points
  // (the frozen rows scored cost far more) and its gains as close to the plant's
  std::printf(
      "[ measured ] own fit %.2f %% (unflagged log %.2f %%); largest gain error %.3f "
      "(unflagged %.3f)\n",
      e.fit_avg, clean.fit_avg, largest_relative_gain_error(e, truth_),
      largest_relative_gain_error(clean, truth_));
  EXPECT_NEAR(e.fit_avg, clean.fit_avg, 2.0)
      << "own fit % on the log with a comm_lost span, expected that of the unflagged log";
  EXPECT_LE(largest_relative_gain_error(e, truth_),
            std::max(0.1, 2.0 * largest_relative_gain_error(clean, truth_)))
      << "largest relative error of an identified gain, expected at most twice the "
         "unflagged log's (or 10 %)";
}

// Issue 45: in the loop the truth is the plant simulated on the gateway's inputs, scored by
// the cross-fit's rule: on an unflagged log it is the fit of the noisy outputs against the
// noise-free ones; with a drop-out the frozen rows count for the truth no more than for the
// model, so its fit stays where it was (scored on every row, the frozen outputs would cost
// it points).
TEST_F(LoopFlags, TheTruthIsThePlantOnTheGatewaysInputsScoredOnTheRowsTheModelIs) {
  const Experiment clean = experiment_on(log_);
  double expected = 0.0;
  for (Eigen::Index j = 0; j < clean.Y.cols(); ++j)
    expected +=
        fit_percent(clean.Y.col(j), clean.Y_clean.col(j)) / static_cast<double>(clean.Y.cols());
  EXPECT_NEAR(clean.truth_fit, expected, 1e-3) << "the log's inputs are the plan's, to its digits";
  EXPECT_LT(clean.fit_avg - clean.truth_fit, 0.5) << "no model predicts the noise";
  runlog::RunLog dropped = log_;
  lose_communication(dropped, 300, 200);
  const Experiment e = experiment_on(dropped);
  std::printf("[ measured ] truth's fit %.2f %% (unflagged %.2f %%), own fit %.2f %%\n",
              e.truth_fit, clean.truth_fit, e.fit_avg);
  EXPECT_NEAR(e.truth_fit, clean.truth_fit, 1.0);
  EXPECT_LT(e.fit_avg - e.truth_fit, 0.5);
}

TEST_F(LoopFlags, APlantRestartStartsANewSegment) {
  // GIVEN the gateway's log with a row flagged discontinuity (the plant restarted there)
  runlog::RunLog restarted = log_;
  const std::size_t at = 400;
  restarted.flags[at] |= runlog::kDiscontinuity;

  // WHEN the campaign runs the experiment on it (a log with a restart is refused by a
  // plain read of its columns: they are not one continuous run)
  const Experiment e = experiment_on(restarted);

  // THEN the model restarts from rest at that row and the warm-up after it is not scored
  ASSERT_EQ(e.layout.segments.size(), 2U);
  EXPECT_EQ(e.layout.segments[1].begin, static_cast<Eigen::Index>(at));
  EXPECT_EQ(e.layout.weight(static_cast<Eigen::Index>(at)), 0.0)
      << "row " << at << " starts a segment inside the run, expected it in the warm-up";
  EXPECT_LT(e.layout.scored(), e.layout.rows());
  EXPECT_GT(e.fit_avg, 50.0);
}

}  // namespace
}  // namespace excite::host
