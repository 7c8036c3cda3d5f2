// SPDX-License-Identifier: MIT
// The noise model of the prediction-error fit (host/identify/noise_model.hpp): its least-
// squares fit and order by BIC, the ARMA(1,1) beside the AR orders, the prefilter per segment,
// the rows the prefilter spoils, and that with the noise model off the fit is identify()'s.
#include "host/identify/noise_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "test_data.hpp"

namespace excite::host {
namespace {

// v(k) = −Σ a_j v(k − j) + e(k), e white of unit variance, from rest.
Eigen::VectorXd ar_process(const std::vector<double>& a, Eigen::Index rows, unsigned seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> e(0.0, 1.0);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(rows);
  for (Eigen::Index k = 0; k < rows; ++k) {
    v(k) = e(g);
    for (std::size_t j = 1; j <= a.size(); ++j) {
      const auto lag = static_cast<Eigen::Index>(j);
      if (k >= lag) v(k) -= a[j - 1] * v(k - lag);
    }
  }
  return v;
}

TEST(ArNoise, RecoversAnAr2ItsOrderAndItsInnovationVariance) {
  // A(q) = 1 − 1.2 q⁻¹ + 0.5 q⁻²: poles at 0.6 ± 0.37i, a slow coloured noise.
  const Eigen::VectorXd v = ar_process({-1.2, 0.5}, 20000, 7);
  const ArNoiseModel m = fit_ar_noise(v, SampleLayout::whole(v.size()), 10);
  ASSERT_EQ(m.order(), 2);
  EXPECT_NEAR(m.a(0), -1.2, 0.02);
  EXPECT_NEAR(m.a(1), 0.5, 0.02);
  EXPECT_NEAR(m.innovation_variance, 1.0, 0.03);
}

TEST(ArNoise, AFirstOrderDisturbanceUnderWhiteNoiseGetsTheArma11AndItsLowFrequencyLevel) {
  // GIVEN the simulator's coloured case: a first-order disturbance of pole 0.95 and std 1 plus
  // white noise of std 1/3, an ARMA(1,1) of zero 0.398 (its innovation form).
  const double pole = 0.95;
  Eigen::VectorXd v = std::sqrt(1.0 - pole * pole) * ar_process({-pole}, 20000, 11);
  v += ar_process({}, 20000, 12) / 3.0;
  // (1 − pole·q⁻¹) v has autocovariances c0 and −c1 at lags 0 and 1, an MA(1) of zero θ
  // with θ/(1 + θ²) = c1/c0.
  const double c0 = (1.0 - pole * pole) + (1.0 + pole * pole) / 9.0;
  const double c1 = pole / 9.0;
  const double zero = (c0 / c1 - std::sqrt(c0 * c0 / (c1 * c1) - 4.0)) / 2.0;
  // WHEN the noise model is fitted
  const ArNoiseModel m = fit_ar_noise(v, SampleLayout::whole(v.size()), 20);
  // THEN BIC prefers the ARMA(1,1) to every AR of order ≤ 20, and the pole and zero are the
  // process's
  ASSERT_TRUE(m.arma.has_value());
  EXPECT_EQ(m.name(), "ARMA(1,1)");
  EXPECT_EQ(m.parameters(), 2);
  EXPECT_NEAR(m.arma->pole, pole, 0.01);
  EXPECT_NEAR(m.arma->zero, zero, 0.03);
  // AND the prefilter, its expansion, has A(1) = (1 − pole)/(1 − zero) to within the cut tail
  // (10⁻³): the disturbance's level at low frequency, what a gain's SE rests on.
  EXPECT_NEAR(1.0 + m.a.sum(), (1.0 - m.arma->pole) / (1.0 - m.arma->zero), 1e-3);
  // AND the prefilter's rows are the ARMA's prediction error
  const SampleLayout whole = SampleLayout::whole(v.size());
  const Eigen::VectorXd x = v.array() - v.mean();
  const Eigen::VectorXd e = arma_prediction_error(x, *m.arma, whole);
  EXPECT_LT((prefilter(x, m, whole).col(0) - e).tail(19000).cwiseAbs().maxCoeff(), 1e-2);
}

// Over replicate records, the spread of ln L̂² (L̂ the fitted level, 1/Â(1)) and the degrees
// of freedom low_frequency_level_dof gives each record, median and median of 2/ν̂.
struct LevelSpread {
  double variance = 0.0;
  double two_over_dof = 0.0;
  int arma = 0;
};

LevelSpread level_spread(double pole, double white_std, Eigen::Index rows, int records) {
  std::vector<double> log_level, two_over_dof;
  LevelSpread out;
  for (int r = 0; r < records; ++r) {
    const auto seed = static_cast<unsigned>(1000 + 2 * r);
    Eigen::VectorXd v = std::sqrt(1.0 - pole * pole) * ar_process({-pole}, rows, seed);
    v += white_std * ar_process({}, rows, seed + 1);
    const SampleLayout whole = SampleLayout::whole(rows);
    const ArNoiseModel m = fit_ar_noise(v, whole, 20);
    out.arma += m.arma ? 1 : 0;
    log_level.push_back(-2.0 * std::log(std::abs(1.0 + m.a.sum())));
    two_over_dof.push_back(2.0 / low_frequency_level_dof(v, m, whole));
  }
  const double mean = std::accumulate(log_level.begin(), log_level.end(), 0.0) / records;
  for (const double x : log_level) out.variance += (x - mean) * (x - mean) / (records - 1);
  std::nth_element(two_over_dof.begin(), two_over_dof.begin() + records / 2, two_over_dof.end());
  out.two_over_dof = two_over_dof[static_cast<std::size_t>(records / 2)];
  return out;
}

TEST(NoiseLevel, ItsDegreesOfFreedomGiveTheSpreadOfTheFittedLevelOverRecords) {
  // An AR(1) of pole 0.9 on 2 000 rows: ν = N(1 − φ)/(2(1 + φ)) = 52.6, Var ln L̂² = 2/ν =
  // 0.038. 200 records: the sample variance is within ±20 % at 95 % (measured: ratio 1.05).
  const LevelSpread ar = level_spread(0.9, 0.0, 2000, 200);
  EXPECT_NEAR(ar.two_over_dof, 2.0 / 52.6, 0.1 * 2.0 / 52.6);
  EXPECT_NEAR(ar.variance / ar.two_over_dof, 1.0, 0.3) << ar.variance;
  // The simulator's case, a disturbance of pole 0.95 under white noise of a third its std:
  // the ARMA(1,1), its pole and zero both uncertain (measured: every record; ratio 1.00).
  const LevelSpread arma = level_spread(0.95, 1.0 / 3.0, 2000, 150);
  EXPECT_GT(arma.arma, 100);
  EXPECT_NEAR(arma.variance / arma.two_over_dof, 1.0, 0.3) << arma.variance;
  // White noise is not a level to estimate: z stands.
  const Eigen::VectorXd white = ar_process({}, 2000, 5);
  const SampleLayout whole = SampleLayout::whole(white.size());
  EXPECT_TRUE(std::isinf(low_frequency_level_dof(white, fit_ar_noise(white, whole, 20), whole)));
}

TEST(ArNoise, WhiteNoiseGetsOrderZeroAndAnOffsetIsNotNoise) {
  // White noise about an offset of 5 (an offset per segment is removed before the fit: a
  // constant would otherwise read as a unit root).
  Eigen::VectorXd v = ar_process({}, 5000, 3);
  v.array() += 5.0;
  const ArNoiseModel m = fit_ar_noise(v, SampleLayout::whole(v.size()), 10);
  EXPECT_EQ(m.order(), 0);
  EXPECT_NEAR(m.innovation_variance, 1.0, 0.06);
}

TEST(ArNoise, RefusesANegativeOrderOrAWrongLengthByName) {
  const Eigen::VectorXd v = ar_process({}, 100, 1);
  try {
    fit_ar_noise(v, SampleLayout::whole(100), -1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "output error rows, AR order = 100, -1, expected 100 rows and an order >= 0");
  }
  EXPECT_THROW(fit_ar_noise(v, SampleLayout::whole(99), 2), std::invalid_argument);
  // Too few rows for the order asked lower it: 100 rows carry at most order 9.
  EXPECT_LE(fit_ar_noise(ar_process({-0.9}, 100, 2), SampleLayout::whole(100), 40).order(), 9);
}

TEST(Prefilter, FiltersEachSegmentFromRestAndSpoilsTheRowsAfterAnUnscoredSpan) {
  SampleLayout layout;
  layout.segments = {{0, 2}, {2, 8}};
  layout.weight = Eigen::VectorXd::Ones(8);
  layout.weight(4) = 0.0;
  ArNoiseModel noise;
  noise.a = Eigen::Vector2d(0.5, -0.25);
  Eigen::MatrixXd X(8, 1);
  X << 1, 2, 3, 4, 5, 6, 7, 8;
  // x(k) + 0.5 x(k − 1) − 0.25 x(k − 2), each segment from rest (rows 0–1, then 2–7).
  Eigen::VectorXd expected(8);
  expected << 1, 2.5, 3, 5.5, 6.25, 7.5, 8.75, 10.0;
  EXPECT_LT((prefilter(X, noise, layout).col(0) - expected).cwiseAbs().maxCoeff(), 1e-12);
  // Row 4 is not scored: it and the two rows after it read it.
  const SampleLayout f = prefiltered_layout(layout, 2);
  Eigen::VectorXd weight(8);
  weight << 1, 1, 1, 1, 0, 0, 0, 1;
  EXPECT_EQ(f.weight, weight);
  EXPECT_EQ(f.segments.size(), 2U);
}

TEST(NoiseModelFit, WithTheNoiseModelOffItIsTheOutputErrorFit) {
  // A 1×2 first-order plant driven by two PRBS, white output noise.
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 7, 5, 40, 1200, 1.0);
  IdentifiedModel truth;
  truth.inputs = 2;
  truth.outputs = 1;
  truth.sample_time_min = 1.0;
  truth.elements.resize(2);
  truth.elements[0].value = ElementModel{2.0, 3.0, 10.0, 0.0};
  truth.elements[1].value = ElementModel{-1.0, 1.0, 6.0, 0.0};
  for (ElementEstimate& e : truth.elements) e.value.structure = Structure::first_order;
  const Eigen::MatrixXd Y = simulate(truth, U) + 0.05 * ar_process({}, 1200, 9);
  IdentifyOptions options;
  options.structure = Structure::first_order;
  const IdentificationResult oe = identify(U, Y, 1.0, options);
  const NoiseModelFit off = identify_with_noise_model(U, Y, 1.0, SampleLayout::whole(1200), options,
                                                      NoiseModelOptions{0, 2});
  EXPECT_EQ(off.noise[0].order(), 0);
  EXPECT_EQ(off.result.model.static_gain(), oe.model.static_gain());
  // White noise: BIC keeps the output-error fit on with the noise model on too.
  const NoiseModelFit on = identify_with_noise_model(U, Y, 1.0, SampleLayout::whole(1200), options);
  EXPECT_EQ(on.noise[0].order(), 0);
  EXPECT_EQ(on.result.model.static_gain(), oe.model.static_gain());
  EXPECT_TRUE(std::isinf(on.result.fits[0].noise_level_dof));  // its level is not estimated
}

}  // namespace
}  // namespace excite::host
