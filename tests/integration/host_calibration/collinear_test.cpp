// SPDX-License-Identifier: MIT
// Inputs that move together never earn a confident grade (issue 43 §3): over many noise
// seeds, with two inputs of a plant made nearly collinear, the nominal 95 % interval of every
// gain and of σ_min must cover the truth in about 95 % of the seeds, and an element graded A
// or B must not have an interval that misses the truth in more than 5 % of them.
//
// The data: the case study's prbsUnc design (independent PRBS per input, SPEC §4), its noise
// (5·10⁻⁴), and input `second` replaced by
//   u_b ← √(1 − ρ²)·(s_b/s_a)·u_a + ρ·u_b      (s: each input's RMS)
// so that ρ of u_b's movement is its own and the rest is u_a's (ρ = 1 %, 10 %, 30 %: a ratio
// station, a cascade, a loosely coupled pair). Before issue 43 the 1 % case put Wood–Berry's
// y1 ← u1 at grade A with the wrong sign (K = −7.7 ± 0.7, true +12.8); until the starts from
// each input's own part (own_part_start.hpp) its intervals covered 22–83 %. alatiqi4x4 at
// 1 % is not calibrated yet (its row y3 covers 67–68 %: host/identify/README.md) and is held
// to the grade and naming checks only.
// EXCITE_COLLINEAR_SEEDS overrides the seed count (default 100); the run prints the table.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/input_screen.hpp"
#include "host/identify/inputs_together.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

int seeds() {
  const char* text = std::getenv("EXCITE_COLLINEAR_SEEDS");
  const int n = text != nullptr ? std::atoi(text) : 100;
  return n > 0 ? n : 100;
}

struct Case {
  std::string plant;
  int first;               // u_a, 0-based
  int second;              // u_b
  double independent;      // ρ
  bool calibrated = true;  // held to the coverage bounds
};

std::string name_of(const ::testing::TestParamInfo<Case>& info) {
  return info.param.plant + "_u" + std::to_string(info.param.first + 1) + "u" +
         std::to_string(info.param.second + 1) + "_" +
         std::to_string(static_cast<int>(std::lround(100.0 * info.param.independent))) + "pct";
}

// u_b made to move with u_a, its own part ρ of its movement.
Eigen::MatrixXd together(Eigen::MatrixXd U, const Case& c) {
  const auto rms = [&](int i) { return U.col(i).norm() / std::sqrt(double(U.rows())); };
  const double share =
      std::sqrt(1.0 - c.independent * c.independent) * rms(c.second) / rms(c.first);
  U.col(c.second) = share * U.col(c.first) + c.independent * U.col(c.second);
  return U;
}

struct Tally {
  int covered = 0;
  int runs = 0;
  int confident_and_wrong = 0;  // grade A or B, the interval missing the truth
  double percent() const { return runs > 0 ? 100.0 * covered / runs : 0.0; }
};

class Collinear : public ::testing::TestWithParam<Case> {};

TEST_P(Collinear, IntervalsCoverTheTruthAndNoConfidentGradeIsWrong) {
  const Case c = GetParam();
  const PriorKnowledge prior = case_study(c.plant);
  const Design design = design_preset(prior, find_preset("prbsUnc"), 0);
  const auto plant = sim::make_plant(c.plant);
  const SimulatedRun base = simulate_plan(*design.plan, "prbsUnc", *plant, SimulationOptions{});
  const Eigen::MatrixXd U = together(base.du, c);
  const double T = base.sample_time_min;
  const Eigen::MatrixXd clean = plant->simulate(U, T);
  const Eigen::MatrixXd truth = plant->static_gain();
  const Eigen::VectorXd true_sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(truth).singularValues();
  const Eigen::Index p = truth.rows(), n = truth.cols(), weak = true_sigma.size() - 1;
  const double noise_sd = std::sqrt(case_study_noise_variance(c.plant));

  std::vector<Tally> gain(static_cast<std::size_t>(p * n));
  Tally sigma_min;
  int named = 0;
  const int S = seeds();
  for (int s = 1; s <= S; ++s) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(s));
    std::normal_distribution<double> noise(0.0, noise_sd);
    Eigen::MatrixXd Y = clean;
    for (Eigen::Index k = 0; k < Y.size(); ++k) Y.data()[k] += noise(rng);
    IdentifyOptions options;
    options.max_time_constant_min = prior.beta * prior.tau_high_min;  // SPEC §6
    options.threads = 2;
    const IdentificationResult r = identify(U, Y, T, options);
    for (Eigen::Index j = 0; j < p; ++j) {
      named += r.fits[static_cast<std::size_t>(j)].inputs_together.empty() ? 0 : 1;
      for (Eigen::Index i = 0; i < n; ++i) {
        const ElementEstimate& e = r.model.element(static_cast<int>(j), static_cast<int>(i));
        Tally& t = gain[static_cast<std::size_t>(j * n + i)];
        ++t.runs;
        const bool covers =
            e.estimated() && std::abs(e.value.gain - truth(j, i)) <= 1.96 * e.std_error.gain;
        t.covered += covers ? 1 : 0;
        t.confident_and_wrong += !covers && e.grade <= Grade::B ? 1 : 0;
      }
    }
    ++sigma_min.runs;
    if (r.gain_uncertainty) {
      const GainUncertainty& u = *r.gain_uncertainty;
      sigma_min.covered +=
          std::abs(u.singular_values(weak) - true_sigma(weak)) <= 1.96 * u.singular_value_se(weak)
              ? 1
              : 0;
    }
  }
  std::printf("%s, u%d with u%d, own part %.0f %%, %d seeds\n", c.plant.c_str(), c.second + 1,
              c.first + 1, 100.0 * c.independent, S);
  for (Eigen::Index j = 0; j < p; ++j) {
    std::printf("  y%ld:", static_cast<long>(j + 1));
    for (Eigen::Index i = 0; i < n; ++i) {
      const Tally& t = gain[static_cast<std::size_t>(j * n + i)];
      std::printf("  %5.1f %% (A/B wrong %d)", t.percent(), t.confident_and_wrong);
    }
    std::printf("\n");
  }
  std::printf("  sigma_min covered %.1f %%; rows naming the inputs together: %d of %ld\n",
              sigma_min.percent(), named, static_cast<long>(S * p));

  // A calibrated 95 % interval misses the truth in 5 % of seeds, by definition, and at 100
  // seeds one element's count scatters by ±2.2 points: the bounds are 3–4 such spreads from
  // 95 % (an element at 87 % or a pooled 92 % is not the draw), and "confident and wrong"
  // (graded A or B, the truth outside) is held to 5 % plus two spreads, rounded up: 10 of 100.
  const int wrong_limit =
      (S * 5 + 99) / 100 + static_cast<int>(std::ceil(2.0 * std::sqrt(S * 0.05 * 0.95)));
  Tally pooled;
  for (std::size_t k = 0; k < gain.size(); ++k) {
    const Tally& t = gain[k];
    const std::string element = "(y" + std::to_string(k / static_cast<std::size_t>(n) + 1) + ", u" +
                                std::to_string(k % static_cast<std::size_t>(n) + 1) + ")";
    EXPECT_LE(t.confident_and_wrong, wrong_limit)
        << element << ": graded A or B, the truth outside";
    pooled.covered += t.covered;
    pooled.runs += t.runs;
    if (!c.calibrated) continue;  // coverage not met there (README, issue 43)
    EXPECT_GE(t.percent(), 87.0) << element;
  }
  std::printf("  every gain pooled: %.1f %%\n", pooled.percent());
  if (c.calibrated) {
    EXPECT_GE(pooled.percent(), 92.0);
    EXPECT_LE(pooled.percent(), 98.0);
    EXPECT_GE(sigma_min.percent(), 87.0);
  }
  if (c.independent < 0.75 * kTogether) {
    EXPECT_EQ(named, S * p) << "every row names the pair";
  }
  if (c.independent > 1.25 * kTogether) {
    EXPECT_EQ(named, 0) << "no row names inputs";
  }
}

INSTANTIATE_TEST_SUITE_P(
    NearlyCollinearInputs, Collinear,
    ::testing::Values(Case{"woodberry2x2", 0, 1, 0.01}, Case{"woodberry2x2", 0, 1, 0.10},
                      Case{"woodberry2x2", 0, 1, 0.30}, Case{"alatiqi4x4", 0, 1, 0.01, false},
                      Case{"alatiqi4x4", 0, 1, 0.10}, Case{"alatiqi4x4", 0, 1, 0.30}),
    name_of);

}  // namespace
}  // namespace excite::host
