// SPDX-License-Identifier: MIT
// Inputs that move together (issue 43 §1, §2): the screen of a row's inputs
// (input_separation), the profile likelihood of a gain (gain_profile.hpp), and the case the
// issue found — Wood–Berry with u2 = u1 ± 1.4 %, where the linearised intervals put y1 ← u1
// at grade A with the wrong sign and det G(0) at 77.75 ± 8.51 (true −123.6) — and the starts
// that find that case's true basin (own_part_start.hpp).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/identify/gain_profile.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/input_screen.hpp"
#include "host/identify/inputs_together.hpp"
#include "host/identify/miso_fit.hpp"
#include "host/identify/own_part_start.hpp"
#include "host/identify/response_bank.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

using testing::add_noise;
using testing::plant_outputs;
using testing::prbs_inputs;

// Wood & Berry (1973), minutes: {K, T_d, T_p1, T_p2}.
const std::vector<ElementModel> kWoodBerry = {{12.8, 1.0, 16.7, 0.0},
                                              {-18.9, 3.0, 21.0, 0.0},
                                              {6.6, 7.0, 10.9, 0.0},
                                              {-19.4, 3.0, 14.4, 0.0}};

// What a two-input row's fit takes besides its data, on 1-min samples: both inputs, the
// thesis's bounds, every row scored, no trend.
struct TwoInputRow {
  explicit TwoInputRow(Eigen::Index N) : layout(SampleLayout::whole(N)), trend(N, 0) {}
  std::vector<int> inputs{0, 1};
  MisoBounds bounds{20.0, 1200.0, natural_period_floor(1.0)};
  SampleLayout layout;
  Eigen::MatrixXd trend;
};

// Row y1 of a 2-input plant `G` on U with noise sd 0.04 of `seed`: identify()'s model, and
// the row refitted from it by fit_miso alone (no profile, no projection) on `r`'s bounds.
struct RefittedRow {
  RefittedRow(const Eigen::MatrixXd& U, const std::vector<ElementModel>& G, unsigned seed,
              const TwoInputRow& r) {
    Eigen::MatrixXd Y = plant_outputs(G, 1, 2, 1.0, U);
    add_noise(Y, 0.04, seed);
    identified = identify(U, Y, 1.0);
    y = Y.col(0);
    const std::vector<ElementModel> start{identified.model.element(0, 0).value,
                                          identified.model.element(0, 1).value};
    fit = fit_miso(U, y, r.inputs, start, 1.0, r.bounds, 200, r.layout, r.trend);
  }
  IdentificationResult identified;
  Eigen::VectorXd y;
  MisoResult fit;
};

TEST(InputSeparation, TheOwnPartOfAColumnIsItsResidualOnTheOthers) {
  const Eigen::MatrixXd moved = prbs_inputs(2, 9, 4, 170, 2044, 1.0);
  const double rho = 0.1;
  Eigen::MatrixXd X(moved.rows(), 2);
  X.col(0) = moved.col(0);
  X.col(1) = 3.0 * (std::sqrt(1.0 - rho * rho) * moved.col(0) + rho * moved.col(1));
  const InputSeparation s = input_separation(X);
  const double r =
      moved.col(0).dot(moved.col(1)) / (moved.col(0).norm() * moved.col(1).norm());  // ≈ 0
  ASSERT_LT(std::abs(r), 0.05);
  EXPECT_NEAR(s.independent(1), rho, 0.01);
  EXPECT_NEAR(s.independent(0), s.independent(1), 1e-12);  // symmetric for two columns
  EXPECT_NEAR(s.regression(0, 1), 3.0 * std::sqrt(1.0 - rho * rho), 0.05);  // x1 ≈ b·x0
  EXPECT_NEAR(s.regression(1, 1), 0.0, 0.0);
  const double c = 1.0 / (rho * rho);  // κ of [[1, a], [a, 1]], a = √(1 − ρ²): (1+a)/(1−a)
  EXPECT_GT(s.condition, 0.5 * c);
  const InputSeparation apart = input_separation(moved);
  EXPECT_GT(apart.independent.minCoeff(), 0.99);
  EXPECT_LT(apart.condition, 1.1);
}

// Where the linearisation holds (independent inputs, small noise), the profile interval is
// the linearised one: it adds honesty where needed, not width everywhere.
TEST(GainProfile, MatchesTheLinearisedIntervalOnIndependentInputs) {
  const Eigen::MatrixXd U = prbs_inputs(2, 8, 3, 85, 1200, 1.0);
  Eigen::MatrixXd Y = plant_outputs(kWoodBerry, 2, 2, 1.0, U);
  add_noise(Y, 0.04, 3);
  const IdentificationResult r = identify(U, Y, 1.0);
  const std::vector<int> inputs{0, 1};
  std::vector<ElementModel> start;
  for (int i = 0; i < 2; ++i) start.push_back(r.model.element(0, i).value);
  const MisoBounds bounds{20.0, 1200.0, natural_period_floor(1.0)};
  const SampleLayout layout = SampleLayout::whole(U.rows());
  const Eigen::MatrixXd trend(U.rows(), 0);
  const Eigen::VectorXd y = Y.col(0);
  const MisoResult fit = fit_miso(U, y, inputs, start, 1.0, bounds, 200, layout, trend);
  const RowProblem row{U, y, inputs, 1.0, bounds, 200, layout, trend};
  for (int e = 0; e < 2; ++e) {
    const GainInterval interval = profile_gain(row, fit, e);
    ASSERT_FALSE(interval.better);
    const double K = fit.elements[static_cast<std::size_t>(e)].value.gain;
    const double half = 1.96 * fit.elements[static_cast<std::size_t>(e)].std_error.gain;
    EXPECT_TRUE(interval.lower_bounded && interval.upper_bounded);
    EXPECT_NEAR(K - interval.lower, half, 0.1 * half) << "element " << e;
    EXPECT_NEAR(interval.upper - K, half, 0.1 * half) << "element " << e;
    EXPECT_NEAR(interval.ridge(e), 1.0, 1e-12);
  }
}

// Row y1 of Wood–Berry with a small slow element of gain K on u2 (two lags of 34.5 min and a
// 6-min delay, as alatiqi4x4's G23), and the 1 200 rows of PRBS it is identified on.
struct SmallSlowElement {
  Eigen::MatrixXd U;
  std::vector<ElementModel> G;
};
SmallSlowElement small_slow_element(double K) {
  return {prbs_inputs(2, 8, 3, 85, 1200, 1.0), {{12.8, 1.0, 16.7, 0.0}, {K, 6.0, 34.5, 34.5}}};
}

// A gain a few standard errors from zero (|K| < 8 SE: kPoorlyDetermined) sits near the
// model's singular point, where K → 0 leaves the element's dynamics undetermined and the
// output error is far from quadratic in K: identify() gives it the profile's interval, which
// the linearised one fell short of. Row y1 of Wood–Berry with a small slow element on u2
// (two lags of 34.5 min and 6 min delay, as alatiqi4x4's G23), K = −0.3 ± about 0.2 at 95 %:
// before, seeds 1 and 2 kept linearised intervals 14 % and 8 % narrower than the profile's.
TEST(GainProfile, AGainNearZeroGetsAtLeastItsProfileInterval) {
  const auto [U, G] = small_slow_element(-0.3);
  const TwoInputRow setup(U.rows());
  const auto& [inputs, bounds, layout, trend] = setup;
  int profiled = 0;
  for (const unsigned seed : {1U, 2U, 3U, 4U, 5U, 6U}) {
    const RefittedRow r(U, G, seed, setup);
    const ElementEstimate& weak = r.identified.model.element(0, 1);
    const MisoResult& fit = r.fit;
    const RowProblem row{U, r.y, inputs, 1.0, bounds, 200, layout, trend};
    const GainInterval interval = profile_gain(row, fit, 1);
    const double K = weak.value.gain;
    if (!poorly_determined(weak) || interval.better) continue;
    ++profiled;
    EXPECT_GE(1.96 * weak.std_error.gain, 0.95 * (interval.upper - interval.lower) / 2.0)
        << "seed " << seed << ": K = " << K << " ± " << 1.96 * weak.std_error.gain << ", profile ["
        << interval.lower << ", " << interval.upper << "]";
  }
  EXPECT_GE(profiled, 3);
}

// The same small element at a third of that gain (K = −0.1, about 2 SE from zero), whose joint
// 95 % region (K, T_d, T_p1 of a first-order fit, or more) reaches K = 0 in most seeds: its
// reported interval is the projection of that region, the profile walked to χ²_p instead of χ²₁,
// reported beside the covariance and never folded into it (gain_profile.hpp,
// project_gains_near_zero). Wider than K ± 1.96·SE, it holds K̂ and the truth. The large
// element, 40 SE from zero with its dynamics determined, needs none.
TEST(GainProfile, AGainItsJointRegionDoesNotTellFromZeroGetsTheRegionsProjection) {
  const auto [U, G] = small_slow_element(-0.1);
  const TwoInputRow setup(U.rows());
  const auto& [inputs, bounds, layout, trend] = setup;
  int projected = 0;
  for (const unsigned seed : {1U, 2U, 3U, 4U, 5U, 6U}) {
    const RefittedRow r(U, G, seed, setup);
    const MisoResult& fit = r.fit;
    const RowProblem row{U, r.y, inputs, 1.0, bounds, 200, layout, trend};
    MisoResult reported = fit;
    project_gains_near_zero(row, reported);
    EXPECT_EQ(reported.gain_covariance, fit.gain_covariance) << "seed " << seed;
    EXPECT_TRUE(projection_needed(fit.elements[0], 1.0).empty()) << "seed " << seed;
    const ElementEstimate& weak = reported.elements[1];
    EXPECT_EQ(weak.std_error.gain, fit.elements[1].std_error.gain);
    if (projection_needed(fit.elements[1], 1.0).empty()) {
      EXPECT_FALSE(weak.projected_gain) << "seed " << seed;
      continue;
    }
    ++projected;
    ASSERT_TRUE(weak.projected_gain) << "seed " << seed;
    std::printf("seed %u: K = %.4f +- %.4f, reported [%.4f, %.4f]\n", seed, weak.value.gain,
                1.96 * weak.std_error.gain, gain_interval_95(weak).lower,
                gain_interval_95(weak).upper);
    const GainBounds b = gain_interval_95(weak);
    const double K = weak.value.gain, half = 1.96 * weak.std_error.gain;
    EXPECT_EQ(b.lower, weak.projected_gain->bounds.lower);
    ASSERT_TRUE(std::isfinite(b.lower) && std::isfinite(b.upper)) << "seed " << seed;
    // Seed 6 ends with an infinite SE: the projection is the only interval its gain gets.
    if (std::isfinite(half)) {
      EXPECT_LE(b.lower, K - half) << "seed " << seed;
      EXPECT_GE(b.upper, K + half) << "seed " << seed;
      EXPECT_GT(b.upper - b.lower, 2.2 * half)
          << "seed " << seed << ": K = " << K << " ± " << half << ", reported [" << b.lower << ", "
          << b.upper << "]";
    }
    // It holds the true gain: seeds 3 and 4 end in the fast basin at K > 0 and reach −0.1
    // only across zero (gain_profile.cpp, across_zero).
    EXPECT_LE(b.lower, G[1].gain) << "seed " << seed;
    EXPECT_GE(b.upper, G[1].gain) << "seed " << seed;
    EXPECT_NE(weak.projected_gain->why.find("joint 95 % region"), std::string::npos);
  }
  EXPECT_GE(projected, 3);
}

// A gain the data tie to a projected one (its ridge, the regression of the row's gains on the
// projected gain: 1.6 here) follows the projection (gain_profile.hpp, ProjectionScope): by its
// whole width read as a χ²₁ interval (the direct fit), or only by what it adds beyond its
// linearised joint region √χ²_p·SE (the two-stage estimate's stage 2). Hand-computed: the
// small gain's SE 0.1, its projection 1.5 times its linearised region for p = 3.
TEST(GainProfile, ATiedGainFollowsAProjectionByItsWholeWidthOrByWhatItAddsBeyondItsRegion) {
  MisoResult fit;
  fit.elements.resize(2);
  fit.gain_covariance.resize(2, 2);
  fit.gain_covariance << 0.04, 0.016, 0.016, 0.01;  // SEs 0.2 and 0.1, correlation 0.8
  for (int e = 0; e < 2; ++e) {
    ElementEstimate& est = fit.elements[static_cast<std::size_t>(e)];
    est.value.gain = e == 0 ? 5.0 : -0.1;
    est.std_error.gain = std::sqrt(fit.gain_covariance(e, e));
    est.covariance(kGain, kGain) = fit.gain_covariance(e, e);
  }
  GainInterval projection;
  projection.root = std::sqrt(chi_square_95(3));
  const double half = 1.5 * projection.root * 0.1;
  projection.lower = -0.1 - half;
  projection.upper = -0.1 + half;
  projection.ridge = Eigen::Vector2d(1.6, 1.0);

  MisoResult whole = fit;  // (half/1.96)² − 0.01 along the ridge: 0.04 + 1.6²·0.035771
  widen_along_ridge(whole, 1, projection);
  EXPECT_NEAR(whole.elements[0].std_error.gain, std::sqrt(0.04 + 2.56 * 0.035771), 1e-5);
  EXPECT_NEAR(whole.elements[1].std_error.gain, half / 1.96, 1e-12);

  MisoResult beyond = fit;  // (1.5·0.1)² − 0.01 along the ridge: 0.04 + 1.6²·0.0125
  widen_along_ridge(beyond, 1, projection, projection.root);
  EXPECT_NEAR(beyond.elements[0].std_error.gain, std::sqrt(0.04 + 2.56 * 0.0125), 1e-12);
  EXPECT_NEAR(beyond.elements[1].std_error.gain, 0.15, 1e-12);
  EXPECT_GT(beyond.elements[0].profile_variance, 0.0);

  // A projection no wider than its linearised region adds nothing beyond it.
  GainInterval linear = projection;
  linear.lower = -0.1 - projection.root * 0.1;
  linear.upper = -0.1 + projection.root * 0.1;
  MisoResult unchanged = fit;
  widen_along_ridge(unchanged, 1, linear, linear.root);
  EXPECT_LT((unchanged.gain_covariance - fit.gain_covariance).norm(), 1e-15);
  EXPECT_NEAR(unchanged.elements[0].std_error.gain, 0.2, 1e-12);
}

// Which gains are projected (projection_needed): a gain 10 SE from zero with its dynamics
// determined is not; one whose joint region reaches zero is; one whose SE is infinite (a
// direction the output does not depend on runs through K) is, as the only interval it gets;
// one without any SE (NaN: not estimated that far) is not.
TEST(GainProfile, AGainWithAnInfiniteStandardErrorIsProjectedAsItsOnlyInterval) {
  ElementEstimate est;
  est.value = {0.5, 2.0, 15.0, 0.0};
  est.value.structure = Structure::first_order;  // K, T_d, T_p1 free
  est.std_error.gain = 0.05;
  EXPECT_EQ(projection_needed(est, 1.0), "");
  est.std_error.gain = 0.2;  // |K| < √χ²₃·SE = 0.56
  EXPECT_EQ(projection_needed(est, 1.0),
            "projected from its joint 95 % region, which reaches K = 0");
  est.std_error.gain = std::numeric_limits<double>::infinity();
  EXPECT_EQ(projection_needed(est, 1.0),
            "projected from its joint 95 % region: its dynamics are not determined");
  EXPECT_FALSE(std::isfinite(gain_interval_95(est).lower));  // until the projection sets one
  est.std_error.gain = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(projection_needed(est, 1.0), "");
}

// The same row. Its small element is −0.1/(34.5s+1)², and where it is fitted first order, the
// projection of a fit that is the estimate (ProjectionScope::fit_is_final) also holds its
// region in two lags (gain_profile.hpp): an interval that holds the own structure's and is
// wider than it. Before an instrumental-variable step (instrument_step_follows) it is the own
// structure's alone.
TEST(GainProfile, AFirstOrderFitsProjectionHoldsItsRegionInTwoLagsWhereTheFitIsTheEstimate) {
  const auto [U, G] = small_slow_element(-0.1);
  const TwoInputRow setup(U.rows());
  const auto& [inputs, bounds, layout, trend] = setup;
  int wider = 0;
  for (const unsigned seed : {1U, 2U, 4U}) {
    const RefittedRow r(U, G, seed, setup);
    const RowProblem row{U, r.y, inputs, 1.0, bounds, 200, layout, trend};
    ASSERT_EQ(r.fit.elements[1].value.structure, Structure::first_order) << "seed " << seed;
    const auto own =
        projected_gain_interval(row, r.fit, 1, ProjectionScope::instrument_step_follows);
    const auto both = projected_gain_interval(row, r.fit, 1, ProjectionScope::fit_is_final);
    ASSERT_TRUE(own && both) << "seed " << seed;
    EXPECT_LE(both->lower, own->lower) << "seed " << seed;
    EXPECT_GE(both->upper, own->upper) << "seed " << seed;
    EXPECT_GT(both->fits, own->fits) << "seed " << seed;
    if (both->upper - both->lower > 1.05 * (own->upper - own->lower)) ++wider;
  }
  EXPECT_EQ(wider, 3);
}

TEST(GainProfile, TheChiSquarePointsAreTheTablesAndOtherDegreesAreRefusedByName) {
  EXPECT_NEAR(chi_square_95(1), 1.96 * 1.96, 2e-3);
  EXPECT_DOUBLE_EQ(chi_square_95(3), 7.815);
  EXPECT_DOUBLE_EQ(chi_square_95(7), 14.067);
  try {
    chi_square_95(8);
    ADD_FAILURE() << "p = 8 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("= 8, expected 1 to 7"), std::string::npos) << e.what();
  }
}

// A row fitted to rounding (noise-free data in its model class) has exact gains: nothing is
// profiled, where a walk would compare costs that differ by rounding noise (a noise-free
// twoweak4x4 run spent half its identification on such walks). With noise, the same row's
// gains are offered to the profile.
TEST(GainProfile, ARowFittedToRoundingIsNotProfiled) {
  const Eigen::MatrixXd U = prbs_inputs(2, 8, 3, 85, 1200, 1.0);
  const auto& [inputs, bounds, layout, trend] = TwoInputRow(U.rows());
  const std::vector<ElementModel> row_model{kWoodBerry[0], kWoodBerry[1]};
  for (const double noise : {0.0, 0.04}) {
    Eigen::MatrixXd Y = plant_outputs(row_model, 1, 2, 1.0, U);
    if (noise > 0.0) add_noise(Y, noise, 1);
    const Eigen::VectorXd y = Y.col(0);
    const MisoResult fit = fit_miso(U, y, inputs, row_model, 1.0, bounds, 200, layout, trend);
    const RowProblem row{U, y, inputs, 1.0, bounds, 200, layout, trend};
    int offered = 0;
    const MisoResult profiled = profile_gains(row, fit, [&](const MisoResult&, int) {
      ++offered;
      return false;
    });
    if (noise > 0.0) {
      EXPECT_EQ(offered, 2);
    } else {
      EXPECT_EQ(offered, 0) << "cost " << row_cost(row, fit) << ", ‖y‖² " << y.squaredNorm();
      EXPECT_EQ(profiled.gain_covariance, fit.gain_covariance);
    }
  }
}

// The case: u2 = u1 + 0.001·(its own PRBS), noise sd 0.02, seeds 5–7. Each row names
// the pair; no element is graded better than C; det G(0) has the true sign or is reported
// undetermined. Before issue 43: y1 ← u1 at grade A with the wrong sign,
// det G(0) = 77.75 ± 8.51.
TEST(InputsTogether, AWoodBerryRunWithTheInputsOnePercentApartStatesNoConfidentWrongGain) {
  for (const unsigned seed : {5U, 6U, 7U}) {
    const Eigen::MatrixXd moved = prbs_inputs(2, 8, 3, 85, 1200, 0.07);
    Eigen::MatrixXd U(moved.rows(), 2);
    U.col(0) = moved.col(0);
    U.col(1) = moved.col(0) + (0.001 / 0.07) * moved.col(1);
    Eigen::MatrixXd Y = plant_outputs(kWoodBerry, 2, 2, 1.0, U);
    add_noise(Y, 0.02 * 0.02, seed);
    const IdentificationResult r = identify(U, Y, 1.0);
    for (int j = 0; j < 2; ++j) {
      const std::string& text = r.fits[static_cast<std::size_t>(j)].inputs_together;
      EXPECT_NE(text.find("input 2 moves with input 1"), std::string::npos)
          << "seed " << seed << ", y" << j + 1 << ": " << text;
      for (int i = 0; i < 2; ++i) {
        const ElementEstimate& e = r.model.element(j, i);
        const double truth = kWoodBerry[static_cast<std::size_t>(2 * j + i)].gain;
        const bool covers = std::abs(e.value.gain - truth) <= 1.96 * e.std_error.gain;
        // At most C: the split rests on the dynamics alone, and an interval is only as good
        // as the search that found the basins (collinear_test.cpp at 1 %: Wood–Berry
        // 96–97 %, alatiqi4x4 91–100 %); an interval that misses is never graded A or B.
        EXPECT_GE(e.grade, Grade::C)
            << "seed " << seed << ", (y" << j + 1 << ", u" << i + 1 << "): K = " << e.value.gain
            << " ± " << 1.96 * e.std_error.gain << ", covers the truth " << covers;
      }
    }
    ASSERT_TRUE(r.gain_uncertainty) << r.gain_unavailable_reason;
    const PrincipalMinor& det = r.gain_uncertainty->principal_minors.back();
    EXPECT_TRUE(det.sign_uncertain || det.value < 0.0)
        << "seed " << seed << ": det G(0) = " << det.value << " ± " << 1.96 * det.std_error
        << " (true −123.6)";
  }
}

// The starts from each input's own part (own_part_start.hpp) on the case: the row
// fitted from the better of the two starts ends in the truth's basin, within ln N σ² of the
// refit from the true elements, where the grid's pair start, the one the row had before, ends
// far above it.
TEST(OwnPartStarts, RowsWhoseInputsAreOnePercentApartReachTheTruthsBasin) {
  const Eigen::MatrixXd moved = prbs_inputs(2, 8, 3, 85, 1200, 0.07);
  Eigen::MatrixXd U(moved.rows(), 2);
  U.col(0) = moved.col(0);
  U.col(1) = moved.col(0) + (0.001 / 0.07) * moved.col(1);
  const auto& [inputs, bounds, layout, trend] = TwoInputRow(U.rows());
  const ResponseBank bank(U, inputs, 1.0, GridSpec{20.0, 1200.0}, layout);
  const OwnPartStarts own(U, inputs, 0, 1, 1.0, 20.0, layout);
  const double variance = 0.02 * 0.02;
  const double ln_N = std::log(static_cast<double>(U.rows()));
  int pair_above = 0;
  for (const unsigned seed : {5U, 6U, 7U}) {
    Eigen::MatrixXd Y = plant_outputs(kWoodBerry, 2, 2, 1.0, U);
    add_noise(Y, variance, seed);
    for (int j = 0; j < 2; ++j) {
      const Eigen::VectorXd y = Y.col(j);
      const auto sse_from = [&](const std::vector<ElementModel>& start) {
        const MisoResult fit = fit_miso(U, y, inputs, start, 1.0, bounds, 200, layout, trend);
        return (fit.y_hat - y).squaredNorm();
      };
      const std::vector<ElementModel> truth{kWoodBerry[static_cast<std::size_t>(2 * j)],
                                            kWoodBerry[static_cast<std::size_t>(2 * j + 1)]};
      const double truths = sse_from(truth);
      const std::vector<ElementModel> pair = bank.elements(bank.choose_pair(y, 0, 1));
      pair_above += sse_from(pair) - truths > ln_N * variance ? 1 : 0;
      const RowProblem row{U, y, inputs, 1.0, bounds, 200, layout, trend};
      double best = std::numeric_limits<double>::infinity();
      for (const auto& start : own.starts(row, bank, pair)) best = std::min(best, sse_from(start));
      EXPECT_LE(best - truths, ln_N * variance)
          << "seed " << seed << ", y" << j + 1 << ": " << (best - truths) / variance
          << " sigma^2 above the truth's refit";
    }
  }
  // What the starts are for: from the pair start alone these rows end elsewhere (6 of 6 when
  // written).
  EXPECT_GE(pair_above, 4) << "of 6 rows";
}

// The exchanged start keeps what the data determine, G_a + β·G_b's gain, and gives each of
// the pair the other's dynamics.
TEST(OwnPartStarts, TheExchangedStartKeepsTheCombinationAndSwapsTheDynamics) {
  const Eigen::MatrixXd moved = prbs_inputs(2, 8, 3, 85, 1200, 0.07);
  Eigen::MatrixXd U(moved.rows(), 2);
  U.col(0) = moved.col(0);
  U.col(1) = 2.0 * moved.col(0) + (0.001 / 0.07) * moved.col(1);
  const OwnPartStarts own(U, {0, 1}, 0, 1, 1.0, 20.0, SampleLayout::whole(U.rows()));
  const std::vector<ElementModel> from{kWoodBerry[0], kWoodBerry[1]};
  const std::vector<ElementModel> x = own.exchanged(from);
  const double beta = U.col(0).dot(U.col(1)) / U.col(0).squaredNorm();
  EXPECT_NEAR(beta, 2.0, 0.01);
  EXPECT_NEAR(x[0].gain + beta * x[1].gain, from[0].gain + beta * from[1].gain, 1e-9);
  EXPECT_EQ(x[0].delay_min, from[1].delay_min);
  EXPECT_EQ(x[0].tau1_min, from[1].tau1_min);
  EXPECT_EQ(x[1].delay_min, from[0].delay_min);
  EXPECT_EQ(x[1].tau1_min, from[0].tau1_min);
}

// Another optimum within the χ²₁ 95 % bound of the least cost is inside the likelihood-ratio
// set, and so is its neighbourhood up to the bound: the split gains' intervals reach past it
// by what is left of the bound there, in its own SEs. One beyond the bound, or on a row
// whose inputs split (own parts above kCannotSplit), changes nothing.
TEST(CoverOtherOptima, AnOptimumWithinTheBoundIsInsideTheIntervalsAndOneBeyondIsNot) {
  const Eigen::MatrixXd moved = prbs_inputs(2, 8, 3, 85, 1200, 0.07);
  const auto& [inputs, bounds, layout, trend] = TwoInputRow(moved.rows());
  for (const double own : {0.001, 0.07}) {
    Eigen::MatrixXd U(moved.rows(), 2);
    U.col(0) = moved.col(0);
    U.col(1) = moved.col(0) + (own / 0.07) * moved.col(1);
    Eigen::MatrixXd Y = plant_outputs(kWoodBerry, 2, 2, 1.0, U);
    add_noise(Y, 0.02 * 0.02, 5);
    const Eigen::VectorXd y = Y.col(0);
    const std::vector<ElementModel> truth{kWoodBerry[0], kWoodBerry[1]};
    const MisoResult fit = fit_miso(U, y, inputs, truth, 1.0, bounds, 200, layout, trend);
    const RowProblem row{U, y, inputs, 1.0, bounds, 200, layout, trend};
    const InputSeparation separation = row_separation(row, fit);
    const bool split = separation.independent.minCoeff() < kCannotSplit;
    ASSERT_EQ(split, own < 0.01) << "own part " << separation.independent.minCoeff();
    const double sse = row_cost(row, fit);
    const double sigma2 = sse / static_cast<double>(U.rows() - 6);
    const Eigen::Vector2d K(fit.elements[0].value.gain, fit.elements[1].value.gain);
    const Eigen::Vector2d far = K + Eigen::Vector2d(5.0, -5.0);
    const Eigen::VectorXd se_far = 2.0 * gain_errors_of(fit);  // a flatter basin there
    for (const double rise : {3.0, 4.5}) {
      MisoResult widened = fit;
      cover_other_optima(row, widened, separation,
                         {{K, sse, gain_errors_of(fit)}, {far, sse + rise * sigma2, se_far}});
      for (std::size_t e = 0; e < 2; ++e) {
        const double half = 1.96 * widened.elements[e].std_error.gain;
        if (split && rise < 1.96 * 1.96) {
          // Past the other optimum by what is left of the bound there, in its SEs.
          const double past =
              1.96 * std::sqrt(1.0 - rise / (1.96 * 1.96)) * se_far(static_cast<Eigen::Index>(e));
          EXPECT_GE(half, (5.0 + past) * (1.0 - 1e-9)) << "own " << own << ", element " << e;
        } else {
          EXPECT_EQ(widened.elements[e].std_error.gain, fit.elements[e].std_error.gain)
              << "own " << own << ", rise " << rise << ", element " << e;
        }
      }
    }
  }
}

}  // namespace
}  // namespace excite::host
