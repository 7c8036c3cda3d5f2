// SPDX-License-Identifier: MIT
#include "host/design/presets.hpp"

#include <gtest/gtest.h>

#include "host/design/case_studies.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/measures/input_measures.hpp"

namespace excite::host {
namespace {

Design design(const char* acronym) {
  return design_preset(case_study("alatiqi4x4"), find_preset(acronym), 0);
}

TEST(CaseStudyGain, HasTheSingularValuesOfSpec) {
  const GainAnalysis a = analyse_gain(case_study("alatiqi4x4").gain);
  ASSERT_EQ(a.singular_values.size(), 4);
  EXPECT_NEAR(a.singular_values(0), 20.470, 0.0005);  // SPEC §7
  EXPECT_NEAR(a.singular_values(1), 10.141, 0.0005);
  EXPECT_NEAR(a.singular_values(2), 5.046, 0.0005);
  EXPECT_NEAR(a.singular_values(3), 0.1635, 0.00005);
  EXPECT_NEAR(a.condition_number, 125.2, 0.05);
}

TEST(CaseStudyGain, EachDirectionInputGivesItsUnitOutputDirection) {
  const GainAnalysis a = analyse_gain(case_study("alatiqi4x4").gain);
  for (Eigen::Index i = 0; i < 4; ++i) {
    const Eigen::VectorXd y = a.gain * (a.input_directions.col(i) / a.singular_values(i));
    EXPECT_TRUE(y.isApprox(a.output_directions.col(i), 1e-12)) << "direction " << i + 1;
  }
}

TEST(Presets, EveryDesignLastsTheCaseStudyLengthAndRespectsTheLimits) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  for (const PresetInfo& preset : presets()) {
    const Design d = design_preset(prior, preset, 0);
    // msGlmZipm: one period of A3's modified zippered spectrum (4713 > 4080 samples).
    EXPECT_EQ(d.table.rows(), preset.acronym == "msGlmZipm" ? 4713 : 4080) << preset.acronym;
    EXPECT_EQ(d.table.cols(), 4) << preset.acronym;
    for (Eigen::Index j = 0; j < 4; ++j) {
      EXPECT_LE(d.table.col(j).maxCoeff(), prior.inputs[static_cast<std::size_t>(j)].max)
          << preset.acronym;
      EXPECT_GE(d.table.col(j).minCoeff(), prior.inputs[static_cast<std::size_t>(j)].min)
          << preset.acronym;
    }
  }
}

// stepSeq: input j moves in [1020 j, 1020 (j+1)): +1 for 330 samples, −1 for 330, then 0.
TEST(Presets, StepSeqMovesOneInputAtATimeUpThenDown) {
  const Design d = design("stepSeq");
  for (Eigen::Index j = 0; j < 4; ++j) {
    const Eigen::Index start = 1020 * j;
    for (Eigen::Index k = 0; k < 4080; ++k) {
      const Eigen::Index t = k - start;
      const double expected = (t >= 0 && t < 330) ? 1.0 : (t >= 330 && t < 660) ? -1.0 : 0.0;
      ASSERT_EQ(d.table(k, j), expected) << "input " << j << " sample " << k;
    }
  }
}

// prbsUnc: every input is the same ±1 sequence, input j delayed by j·16 switching intervals.
TEST(Presets, PrbsUncChannelsAreCircularlyShiftedCopies) {
  const Design d = design("prbsUnc");
  const Eigen::Index shift = 16 * 16;  // d = 16 intervals of 16 samples
  for (Eigen::Index j = 1; j < 4; ++j) {
    for (Eigen::Index k = 0; k < 4080; ++k) {
      ASSERT_EQ(d.table(k, j), d.table((k + j * shift) % 4080, 0))
          << "input " << j << " sample " << k;
    }
  }
  EXPECT_EQ(d.table.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_EQ(d.table.cwiseAbs().minCoeff(), 1.0);
}

// u = c V Σ⁻¹ s ⇒ G(0) u = c W s: the projections w_iᵀ y are c·s_i, shifted copies of one
// ±1 sequence, so over the period their variances are equal (5.5.2).
TEST(Presets, PrbsSimDirGivesOutputProjectionsOfEqualVariance) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const GainAnalysis a = analyse_gain(prior.gain);
  const Design d = design("prbsSimDir");
  const Eigen::MatrixXd y = d.table * prior.gain.transpose();
  const Eigen::MatrixXd projections = y * a.output_directions;
  Eigen::VectorXd variance(4);
  for (Eigen::Index i = 0; i < 4; ++i) {
    const Eigen::VectorXd p = projections.col(i).array() - projections.col(i).mean();
    variance(i) = p.squaredNorm() / static_cast<double>(p.size());
  }
  EXPECT_GT(variance.minCoeff(), 0.0);
  EXPECT_NEAR(variance.minCoeff() / variance.maxCoeff(), 1.0, 1e-9);
}

TEST(Presets, DirectionalDesignsAreScaledToTheInputLimitsHere) {
  const Design d = design("prbsSimDir");
  EXPECT_NEAR(d.table.cwiseAbs().maxCoeff(), 2.0, 1e-9);  // limits ±2 bind on this plant
}

// Zhu's combined design: the inputs minus the uncorrelated part lie along v_n.
TEST(Presets, PrbsDirCorrSimAddsASignalAlongTheWeakestDirection) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const GainAnalysis a = analyse_gain(prior.gain);
  const Design d = design("prbsDirCorrSim");
  const signal::Recipe& r = d.plan->recipe;
  ASSERT_EQ(r.source_count, 5U);
  Eigen::VectorXd correlated(4);
  for (std::size_t c = 0; c < 4; ++c) correlated(static_cast<Eigen::Index>(c)) = r.mix[c][4];
  EXPECT_NEAR(std::abs(correlated.normalized().dot(a.input_directions.col(3))), 1.0, 1e-12);
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t i = 0; i < 4; ++i) {
      if (i != c) {
        EXPECT_EQ(r.mix[c][i], 0.0);  // uncorrelated part: one source per input
      }
    }
  }
}

TEST(Presets, SequentialMultisinesPlayWholePeriodsOneChannelAtATime) {
  const Design d = design("msSrdSeq");
  const signal::Recipe& r = d.plan->recipe;
  ASSERT_EQ(r.source_count, 4U);
  for (std::uint32_t i = 0; i < 4; ++i) {
    const signal::Source& s = r.sources[i];
    EXPECT_EQ(s.kind, signal::SourceKind::multisine);
    EXPECT_EQ(s.start, i * 1020U);                      // slot of N/n samples
    EXPECT_EQ(s.length % s.multisine.period, 0U) << i;  // whole periods
    EXPECT_EQ(s.multisine.period, 943U);                // A2: N_s >= 2*pi*beta*tau_H/T (4.4.27)
  }
}

TEST(Presets, GuillaumePhasesLowerTheCrestFactorOfTheSameSpectrum) {
  const double schroeder = measure_inputs(design("msSrdSim").table).average.crest_factor;
  const double guillaume = measure_inputs(design("msGlmSim").table).average.crest_factor;
  EXPECT_LT(guillaume, schroeder - 0.2) << schroeder << " -> " << guillaume;
}

// 4.4.21: the shared (correlated) lines move the inputs along v_n only.
TEST(Presets, ModifiedZipperedSharesLinesAlongTheWeakestDirection) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const GainAnalysis a = analyse_gain(prior.gain);
  const Design d = design("msGlmZipm");
  const signal::Recipe& r = d.plan->recipe;
  ASSERT_EQ(r.source_count, 5U);  // 4 own zippered sources + 1 shared
  Eigen::VectorXd shared(4);
  for (std::size_t c = 0; c < 4; ++c) shared(static_cast<Eigen::Index>(c)) = r.mix[c][4];
  EXPECT_NEAR(std::abs(shared.normalized().dot(a.input_directions.col(3))), 1.0, 1e-12);
}

TEST(Presets, TableLargerThanTheGatewayCapacityIsRefused) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.sample_time_min = 0.0625;  // 16× the samples: 4 × 65 280 values > 2^18
  try {
    design_preset(prior, find_preset("prbsUnc"), 0);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("capacity"), std::string::npos) << e.what();
  }
}

TEST(Presets, UnknownAcronymListsTheKnownOnes) {
  try {
    find_preset("prbsFoo");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("prbsSimDir"), std::string::npos) << e.what();
  }
}

TEST(Presets, DirectionalDesignWithoutGainIsRefused) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.gain.resize(0, 0);
  EXPECT_THROW(design_preset(prior, find_preset("stepDir"), 0), std::invalid_argument);
  EXPECT_NO_THROW(design_preset(prior, find_preset("stepSeq"), 0));
}

}  // namespace
}  // namespace excite::host
