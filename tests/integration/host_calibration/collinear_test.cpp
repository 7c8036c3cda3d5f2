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
// each input's own part (own_part_start.hpp) its intervals covered 22–83 %. alatiqi4x4's row
// y3 at 1 % covered 67–68 % until the starts along the combination and the other optima's
// neighbourhoods in the likelihood-ratio set (host/identify/README.md).
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
  int first;           // u_a, 0-based
  int second;          // u_b
  double independent;  // ρ
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

// The case's inputs (the case study's prbsUnc run, u_b made to move with u_a) and sample time.
struct CaseRun {
  Eigen::MatrixXd U;
  double T = 0.0;
};

CaseRun case_run(const Case& c, const PriorKnowledge& prior, sim::Plant& plant) {
  const Design design = design_preset(prior, find_preset("prbsUnc"), 0);
  const SimulatedRun base = simulate_plan(*design.plan, "prbsUnc", plant, SimulationOptions{});
  return {together(base.du, c), base.sample_time_min};
}

// The identify() options of the case study (SPEC §6).
IdentifyOptions case_options(const PriorKnowledge& prior) {
  IdentifyOptions options;
  options.max_time_constant_min = prior.beta * prior.tau_high_min;
  options.threads = 2;
  return options;
}

// Noise of the case study's variance, seed s.
Eigen::MatrixXd with_noise(Eigen::MatrixXd Y, double noise_sd, int s) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(s));
  std::normal_distribution<double> noise(0.0, noise_sd);
  for (Eigen::Index k = 0; k < Y.size(); ++k) Y.data()[k] += noise(rng);
  return Y;
}

class Collinear : public ::testing::TestWithParam<Case> {};

TEST_P(Collinear, IntervalsCoverTheTruthAndNoConfidentGradeIsWrong) {
  const Case c = GetParam();
  const PriorKnowledge prior = case_study(c.plant);
  const auto plant = sim::make_plant(c.plant);
  const auto [U, T] = case_run(c, prior, *plant);
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
    const IdentificationResult r =
        identify(U, with_noise(clean, noise_sd, s), T, case_options(prior));
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
    EXPECT_GE(t.percent(), 87.0) << element;
  }
  std::printf("  every gain pooled: %.1f %%\n", pooled.percent());
  EXPECT_GE(pooled.percent(), 92.0);
  EXPECT_LE(pooled.percent(), 98.0);
  EXPECT_GE(sigma_min.percent(), 87.0);
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
                      Case{"woodberry2x2", 0, 1, 0.30}, Case{"alatiqi4x4", 0, 1, 0.01},
                      Case{"alatiqi4x4", 0, 1, 0.10}, Case{"alatiqi4x4", 0, 1, 0.30}),
    name_of);

// alatiqi4x4's row y3 at a 1 % own part of u2 (1.73 e^−18s/(13s+1)² and 5.11 e^−12s/(13.3s+1)²
// on u1 and u2, alike but for 6 min of delay): on seeds 3, 6 and 8 the row ended 6.2, 4.0 and
// 9.4 σ̂² above the refit from the true elements, u2's element carrying the combination and
// u1's a small fast correction, its intervals missing the truth: beyond the χ²₁ 95 % point,
// a row's intervals are built around the wrong optimum. The starts along the combination
// (OwnPartStarts::shared) take it to within that point of the refit.
TEST(CollinearStarts, AlatiqiRowY3AtAOnePercentOwnPartEndsInTheTruthsBasin) {
  const Case c{"alatiqi4x4", 0, 1, 0.01};
  const PriorKnowledge prior = case_study(c.plant);
  const auto plant = sim::make_plant(c.plant);
  const auto [U, T] = case_run(c, prior, *plant);
  const Eigen::MatrixXd clean = plant->simulate(U, T);
  const double noise_sd = std::sqrt(case_study_noise_variance(c.plant));
  const int row = 2;
  // The library's row y3 (sim/library/plants.cpp).
  const std::vector<ElementModel> truth{
      {1.73, 18.0, 13.0, 13.0, 0.0, 0.0, 1.0, Structure::two_poles},
      {5.11, 12.0, 13.3, 13.3, 0.0, 0.0, 1.0, Structure::two_poles},
      {4.61, 1.01, 18.5, 0.0, 0.0, 0.0, 1.0, Structure::first_order},
      {-5.49, 1.5, 15.0, 0.0, 0.0, 0.0, 1.0, Structure::first_order}};
  for (const int s : {3, 6, 8}) {
    const Eigen::MatrixXd Y = with_noise(clean, noise_sd, s);
    const IdentifyOptions options = case_options(prior);
    const IdentificationResult found = identify(U, Y, T, options);
    IdentifyOptions from_truth = options;
    from_truth.start = found.model;
    for (int i = 0; i < 4; ++i)
      from_truth.start->element(row, i).value = truth[static_cast<std::size_t>(i)];
    from_truth.start_use = IdentifyOptions::StartUse::polish;
    const IdentificationResult refit = identify(U, Y, T, from_truth);
    const auto sse = [&](const IdentifiedModel& m) {
      return (simulate(m, U).col(row) - Y.col(row)).squaredNorm();
    };
    const double sigma2 = sse(found.model) / static_cast<double>(Y.rows());
    EXPECT_LE((sse(found.model) - sse(refit.model)) / sigma2, 1.96 * 1.96)
        << "seed " << s << ": K31 = " << found.model.element(row, 0).value.gain
        << ", K32 = " << found.model.element(row, 1).value.gain
        << " (the refit from the truth: " << refit.model.element(row, 0).value.gain << ", "
        << refit.model.element(row, 1).value.gain << ")";
  }
}

}  // namespace
}  // namespace excite::host
