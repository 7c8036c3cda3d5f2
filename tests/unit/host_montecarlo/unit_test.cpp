// SPDX-License-Identifier: MIT
// One (design, seed) unit is the campaign's experiment: with all 17 designs, Monte Carlo seed
// s gives exactly what `excite campaign --seed 100s` gives that design (own fit, worst and
// average cross-fit, balance, identified σ_i), bit for bit.
#include <gtest/gtest.h>

#include "host/campaign/campaign.hpp"
#include "host/montecarlo/unit.hpp"

namespace mc = excite::host::montecarlo;

TEST(Unit, EqualsTheCampaignsExperimentOfSeedHundredTimesS) {
  mc::Config config;
  config.plant = "woodberry2x2";
  config.seeds = 1;
  config.first_seed = 2;
  config.noise_variance = 5e-4;
  config.length_step_percent = 50;
  mc::normalise(config);
  const auto prepared = mc::prepare(config, 2);

  excite::host::CampaignOptions options;
  options.plant = "woodberry2x2";
  options.seed = 200;
  options.noise_variance = 5e-4;
  const excite::host::CampaignResult campaign = excite::host::run_campaign(options, {});

  for (const int d : {0, 5, 16}) {  // stepSeq, prbsSimDir, msGlmZipm
    const mc::UnitResult u = mc::run_unit(*prepared, {d, 2, d});
    const excite::host::Experiment& e = campaign.experiments[static_cast<std::size_t>(d)];
    SCOPED_TRACE(e.name);
    EXPECT_EQ(u.design, e.name);
    EXPECT_EQ(u.fit_avg, e.fit_avg);
    EXPECT_EQ(u.crossfit_worst, e.crossfit_worst);
    EXPECT_EQ(u.crossfit_avg, e.crossfit_avg);
    EXPECT_EQ(u.ratio, e.balance_clean.ratio);
    EXPECT_EQ(u.upsilon_noisy, e.balance_noisy.upsilon);
    ASSERT_TRUE(e.identified.gain);
    ASSERT_EQ(u.singular_values.size(), 2U);
    EXPECT_EQ(u.singular_values[1], e.identified.gain->singular_values(1));
    ASSERT_EQ(u.lengths.size(), 2U);  // 50 %, 100 %
    EXPECT_EQ(u.lengths[0].samples, u.samples / 2);
    EXPECT_EQ(u.lengths[1].met, u.accuracy.met);
  }
}

// alatiqi4x4 msSrdSimDir, seed 187, on the first 20 % of the run (816 rows): the identifier
// restarted a weak element from a start the exact discretisation cannot take, and the whole
// unit (a Slurm shard of 170 units with it) ended in "discretisation … gives non-finite
// coefficients". Such a start is now not tried; the unit completes.
TEST(Unit, ARestartTheDiscretisationCannotTakeIsSkippedNotFatal) {
  mc::Config config;
  config.plant = "alatiqi4x4";
  config.designs = {"msSrdSimDir"};
  config.seeds = 1;
  config.first_seed = 187;
  config.noise_variance = 5e-4;
  config.length_step_percent = 20;
  mc::normalise(config);
  const auto prepared = mc::prepare(config, 1);
  const mc::UnitResult u = mc::run_unit(*prepared, {0, 187, 0});
  ASSERT_EQ(u.lengths.size(), 5U);  // 20, 40, 60, 80, 100 %
  EXPECT_EQ(u.lengths[0].samples, 816);
  EXPECT_TRUE(u.lengths.back().met);
}
