// SPDX-License-Identifier: MIT
#include "host/design/presets.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <utility>

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

// |G(0) e_j|: the static output norm input j gives alone.
double column_norm(Eigen::Index j) {
  return case_study("alatiqi4x4").gain.col(j).norm();
}

// Every design as long as every other (issue 23 §1, SPEC §4, thesis §6.3: T_L = 4080 min for
// all): A1's 4080 samples. The simultaneous multisines hold at least one whole period and
// continue it to 4080; the sequential ones give each channel a slot of 1020 samples holding
// at least one whole period of A2's standard multisine (period ≈ 2π β τ_H = 943).
TEST(Presets, EveryDesignLasts4080SamplesAndRespectsTheLimits) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  for (const PresetInfo& preset : presets()) {
    const Design d = design_preset(prior, preset, 0);
    const signal::Recipe& r = d.plan->recipe;
    EXPECT_EQ(d.table.rows(), 4080) << preset.acronym;
    EXPECT_EQ(r.samples, 4080U) << preset.acronym;
    if (preset.acronym.starts_with("ms")) {
      const bool sequential = preset.acronym.find("Seq") != std::string_view::npos;
      for (std::uint32_t i = 0; i < r.source_count; ++i) {
        const signal::Source& src = r.sources[i];
        EXPECT_GE(src.length, src.multisine.period) << preset.acronym << " source " << i;
        EXPECT_EQ(src.length, sequential ? 1020U : 4080U) << preset.acronym << " source " << i;
        if (sequential) {
          EXPECT_EQ(src.multisine.period, 943U) << preset.acronym;
        }
      }
    }
    EXPECT_EQ(d.table.cols(), 4) << preset.acronym;
    EXPECT_EQ(d.limit_scale, 1.0) << preset.acronym << ": limits ±15 leave every design whole";
    for (Eigen::Index j = 0; j < 4; ++j) {
      EXPECT_LE(d.table.col(j).maxCoeff(), prior.inputs[static_cast<std::size_t>(j)].max)
          << preset.acronym;
      EXPECT_GE(d.table.col(j).minCoeff(), prior.inputs[static_cast<std::size_t>(j)].min)
          << preset.acronym;
    }
  }
}

// stepSeq (c = 1.2): input j moves in [1020 j, 1020 (j+1)): +1.2/|G e_j| for 330 samples,
// −1.2/|G e_j| for 330, then 0, so that input j alone gives a static output of norm 1.2.
TEST(Presets, StepSeqMovesOneInputAtATimeByItsStaticOutputSize) {
  const Design d = design("stepSeq");
  for (Eigen::Index j = 0; j < 4; ++j) {
    const Eigen::Index start = 1020 * j;
    const double a = 1.2 / column_norm(j);
    for (Eigen::Index k = 0; k < 4080; ++k) {
      const Eigen::Index t = k - start;
      const double expected = (t >= 0 && t < 330) ? a : (t >= 330 && t < 660) ? -a : 0.0;
      ASSERT_NEAR(d.table(k, j), expected, 1e-12) << "input " << j << " sample " << k;
    }
  }
}

// Multisines are sized on RMS: RMS_j · |G(0) e_j| = c (0.91 for msGlmSim, 1.28 msSrdSeq,
// the RMS of a sequential channel taken over its own period).
TEST(Presets, MultisinesAreSizedOnTheirRms) {
  for (const auto& [acronym, c] : {std::pair{"msGlmSim", 0.91}, std::pair{"msSrdSeq", 1.28}}) {
    const Design d = design(acronym);
    const std::uint32_t period = d.plan->recipe.sources[0].multisine.period;
    for (Eigen::Index j = 0; j < 4; ++j) {
      const auto start =
          static_cast<Eigen::Index>(d.plan->recipe.sources[static_cast<std::size_t>(j)].start);
      const auto one_period = d.table.col(j).segment(start, period);
      const double rms = std::sqrt(one_period.squaredNorm() / period);
      EXPECT_NEAR(rms * column_norm(j), c, 1e-9) << acronym << " input " << j;
    }
  }
}

// prbsUnc: every input is the same ±1 sequence, input j delayed by j·16 switching intervals.
TEST(Presets, PrbsUncChannelsAreCircularlyShiftedCopies) {
  const Design d = design("prbsUnc");
  const Eigen::Index shift = 16 * 16;  // d = 16 intervals of 16 samples
  for (Eigen::Index j = 1; j < 4; ++j) {
    for (Eigen::Index k = 0; k < 4080; ++k) {
      ASSERT_NEAR(d.table(k, j) * column_norm(j),
                  d.table((k + j * shift) % 4080, 0) * column_norm(0), 1e-12)
          << "input " << j << " sample " << k;
    }
  }
  // c = 1.0: input j moves by ±1/|G e_j|, all the time.
  for (Eigen::Index j = 0; j < 4; ++j) {
    EXPECT_NEAR(d.table.col(j).cwiseAbs().maxCoeff(), 1.0 / column_norm(j), 1e-12);
    EXPECT_NEAR(d.table.col(j).cwiseAbs().minCoeff(), 1.0 / column_norm(j), 1e-12);
  }
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

// prbsSimDir (c = 0.4): u = 0.4 V Σ⁻¹ s with s_i = ±1, so every projection w_iᵀ G(0) u
// moves by ±0.4.
TEST(Presets, DirectionalDesignsMoveEveryOutputDirectionByC) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const GainAnalysis a = analyse_gain(prior.gain);
  const Eigen::MatrixXd projections =
      design("prbsSimDir").table * prior.gain.transpose() * a.output_directions;
  for (Eigen::Index i = 0; i < 4; ++i)
    EXPECT_NEAR(projections.col(i).cwiseAbs().maxCoeff(), 0.4, 1e-9) << "direction " << i + 1;
}

// Input limits are separate from the size: a design that does not fit is scaled as a
// whole (every value by one factor, so directions are kept), never clipped per channel.
TEST(Presets, ADesignThatDoesNotFitTheLimitsIsScaledAsAWhole) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  const Design free = design_preset(prior, find_preset("prbsSeqDir"), 0);
  for (InputSpec& in : prior.inputs) {
    in.amplitude = 0.5;
    in.min = -1.0;
    in.max = 1.0;
  }
  const Design bound = design_preset(prior, find_preset("prbsSeqDir"), 0);
  const double peak = free.table.cwiseAbs().maxCoeff();
  ASSERT_GT(peak, 1.0);
  EXPECT_NEAR(bound.limit_scale, 1.0 / peak, 1e-9);
  EXPECT_TRUE(bound.table.isApprox(bound.limit_scale * free.table, 1e-12));
  EXPECT_LE(bound.table.cwiseAbs().maxCoeff(), 1.0);
  bool said = false;
  for (const std::string& note : bound.notes) said |= note.find("scaled by") != std::string::npos;
  EXPECT_TRUE(said);
}

// Issue 14 §7: a plain multisine whose amplitude equals its limit passes design's own check.
TEST(Presets, PlainMultisineAtItsLimitPassesTheLimitCheck) {
  PriorKnowledge prior;
  prior.plant = "test";
  prior.inputs = {{"u", 5.4714, -5.4714, 5.4714}};
  PlainMultisine spec;
  spec.period = 256;
  spec.first_line = 1;
  spec.last_line = 31;
  const Design d = design_plain_multisine(prior, spec, 0);
  EXPECT_LE(d.table.cwiseAbs().maxCoeff(), 5.4714);
  EXPECT_NEAR(d.table.cwiseAbs().maxCoeff(), 5.4714, 1e-9);
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

// Issue 23 §1: a sequential multisine plays A2's standard multisine on channel i alone in
// samples [1020 i, 1020 (i+1)), continued periodically past its period (not padded with
// zeros): the slot is the periodic signal, its crest factor its period's to within the
// partial period's RMS, and over the experiment each channel's crest factor about twice
// (√4) its slot's — the thesis's "sequential CF twice the simultaneous one".
TEST(Presets, SequentialMultisinesPlayOneChannelPerSlotContinuingThePeriod) {
  for (const char* seq : {"msSrdSeq", "msGlmSeq"}) {
    const Design s = design(seq);
    ASSERT_EQ(s.plan->recipe.source_count, 4U);
    const InputMeasures whole = measure_inputs(s.table);
    for (std::uint32_t i = 0; i < 4; ++i) {
      const signal::Source& src = s.plan->recipe.sources[i];
      const std::uint32_t period = src.multisine.period;
      EXPECT_EQ(src.start, i * 1020) << seq;
      EXPECT_EQ(src.length, 1020U) << seq;
      const Eigen::VectorXd slot = s.table.col(i).segment(i * 1020, 1020);
      for (Eigen::Index k = period; k < 1020; ++k)  // continued, not zero
        ASSERT_NEAR(slot(k), slot(k - period), 1e-12) << seq << " " << i << " k " << k;
      if (i > 0) {
        EXPECT_EQ(s.table.col(i).head(i * 1020).cwiseAbs().maxCoeff(), 0.0) << seq;
      }
      const InputMeasures own = measure_inputs(slot);
      const InputMeasures one_period = measure_inputs(slot.head(period));
      EXPECT_NEAR(own.channels[0].crest_factor, one_period.channels[0].crest_factor, 0.02) << seq;
      EXPECT_NEAR(whole.channels[i].crest_factor, 2.0 * own.channels[0].crest_factor,
                  0.01 * whole.channels[i].crest_factor)
          << seq << " " << i;
    }
  }
}

// Issue 23 §2: `excite design` shows the optimiser's run — its L_p schedule and every
// channel's crest factor from the Schroeder start to the result — and the result is lower.
TEST(Presets, GuillaumeDesignsSayTheOptimisersRunWhichLowersTheWorstChannel) {
  for (const char* name : {"msGlmZipm", "msGlmSim", "msGlmSeq"}) {
    const Design d = design(name);
    std::string note;
    for (const std::string& n : d.notes) {
      if (n.rfind("Guillaume optimiser:", 0) == 0) note = n;
    }
    ASSERT_FALSE(note.empty()) << name;
    EXPECT_NE(note.find("p = 4, 8, 16, 32, 64, 128, 256, 512"), std::string::npos) << note;
    double start = 0.0, result = 0.0;
    const std::size_t at = note.find("worst channel's crest factor ");
    ASSERT_NE(at, std::string::npos) << note;
    ASSERT_EQ(
        std::sscanf(note.c_str() + at, "worst channel's crest factor %lf -> %lf", &start, &result),
        2)
        << note;
    EXPECT_LT(result, start - 0.2) << note;
    EXPECT_GT(result, 1.0) << note;
  }
}

TEST(Presets, GuillaumePhasesLowerTheCrestFactorOfTheSameSpectrum) {
  const double schroeder = measure_inputs(design("msSrdSim").table).average.crest_factor;
  const double guillaume = measure_inputs(design("msGlmSim").table).average.crest_factor;
  EXPECT_LT(guillaume, schroeder - 0.2) << schroeder << " -> " << guillaume;
}

// Issue 23 §2: msGlmZipm's optimiser lowers the inputs' average crest factor (the
// worst-input objective held it at 1.523; now 1.461 on alatiqi4x4).
TEST(Presets, ModifiedZipperedAverageCrestFactorIsLowered) {
  const InputMeasures m = measure_inputs(design("msGlmZipm").table);
  EXPECT_LT(m.average.crest_factor, 1.48)
      << "msGlmZipm's average crest factor over its inputs, expected below 1.48 (1.523 with "
         "the worst-input objective)";
  EXPECT_GT(m.average.crest_factor, 1.3);
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

TEST(Presets, StaticOutputSizingRefusesAnInputWithoutStaticEffect) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.gain.col(2).setZero();
  try {
    design_preset(prior, find_preset("prbsUnc"), 0);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gain: column 2 is zero"), std::string::npos) << e.what();
  }
  prior.sizing = Sizing::input_amplitude;
  EXPECT_NO_THROW(design_preset(prior, find_preset("prbsUnc"), 0));
}

TEST(Presets, DirectionalDesignWithoutGainIsRefused) {
  PriorKnowledge prior = case_study("alatiqi4x4");
  prior.gain.resize(0, 0);
  EXPECT_THROW(design_preset(prior, find_preset("stepDir"), 0), std::invalid_argument);
  EXPECT_NO_THROW(design_preset(prior, find_preset("stepSeq"), 0));
}

}  // namespace
}  // namespace excite::host
