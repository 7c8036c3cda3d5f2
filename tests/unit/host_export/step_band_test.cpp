// SPDX-License-Identifier: MIT
// The ±2σ band of an identified element's step response (linearised propagation of the
// parameter covariance, host/export/step_response.hpp): it scales with the standard errors,
// it uses the covariance, and in a seeded noisy identification it contains the true response.

#include <gtest/gtest.h>

#include <cmath>

#include "../host_identify/test_data.hpp"
#include "host/export/step_response.hpp"
#include "host/identify/identify.hpp"

namespace excite::host {
namespace {

std::vector<double> minutes(int count, double step) {
  std::vector<double> t;
  for (int k = 0; k <= count; ++k) t.push_back(k * step);
  return t;
}

ElementEstimate with_errors(double scale) {
  ElementEstimate e;
  e.value = {2.0, 3.0, 20.0, 5.0};
  const Eigen::Vector4d se(0.05, 0.4, 1.5, 0.8);
  e.std_error = {se(0) * scale, se(1) * scale, se(2) * scale, se(3) * scale};
  e.covariance.setConstant(std::nan(""));
  e.covariance.topLeftCorner<4, 4>() = (se * scale).array().square().matrix().asDiagonal();
  e.covariance(kGain, kTp1) = e.covariance(kTp1, kGain) = 0.5 * se(0) * se(2) * scale * scale;
  return e;
}

TEST(StepBand, WidensInProportionToTheStandardErrors) {
  const std::vector<double> t = minutes(100, 1.0);
  const StepBand narrow = step_band(with_errors(1.0), t);
  const StepBand wide = step_band(with_errors(3.0), t);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(narrow.response[k], wide.response[k]);
    if (t[k] < 3.0) {
      EXPECT_EQ(narrow.sigma[k], 0.0) << t[k];  // before T_d: s = 0 exactly
    }
    if (t[k] <= 3.0) continue;
    EXPECT_GT(wide.sigma[k], narrow.sigma[k]) << t[k];
    EXPECT_NEAR(wide.sigma[k], 3.0 * narrow.sigma[k], 1e-6 * wide.sigma[k]) << t[k];
  }
  // Settled: only K is uncertain, σ_s → SE(K) = 0.05.
  EXPECT_NEAR(step_band(with_errors(1.0), {400.0}).sigma[0], 0.05, 1e-6);
}

// The covariance, not only the standard errors: a positive K–T_p1 correlation changes the
// band where both matter; without a covariance the standard errors alone are used.
TEST(StepBand, UsesTheCovarianceWhenGivenAndTheStandardErrorsOtherwise) {
  const ElementEstimate correlated = with_errors(1.0);
  ElementEstimate diagonal = correlated;
  diagonal.covariance(kGain, kTp1) = diagonal.covariance(kTp1, kGain) = 0.0;
  ElementEstimate no_covariance = correlated;
  no_covariance.covariance.setConstant(std::nan(""));
  const std::vector<double> t = {30.0};
  EXPECT_NE(step_band(correlated, t).sigma[0], step_band(diagonal, t).sigma[0]);
  EXPECT_NEAR(step_band(no_covariance, t).sigma[0], step_band(diagonal, t).sigma[0], 1e-12);
  // A parameter on its bound (NaN) counts as exact; one the data do not determine (inf)
  // leaves the band unknown.
  ElementEstimate undetermined = diagonal;
  undetermined.covariance.row(kTp2).setConstant(INFINITY);
  undetermined.covariance.col(kTp2).setConstant(INFINITY);
  EXPECT_TRUE(std::isinf(step_band(undetermined, t).sigma[0]));
}

// Where a projection widens the reported gain interval (alatiqi4x4's G23 under its DMC), the
// settled band holds it: ±1.96σ reaches the interval's farther end. One within K ± 1.96·SE
// changes nothing.
TEST(StepBand, SettlesOnTheReportedGainIntervalWhereAProjectionWidensIt) {
  ElementEstimate projected = with_errors(1.0);  // K = 2 ± 0.098
  projected.projected_gain = ProjectedGain{{1.5, 2.3}, "its joint region reaches K = 0"};
  EXPECT_NEAR(step_band(projected, {400.0}).sigma[0], 0.5 / 1.96, 1e-6);
  const std::vector<double> t = minutes(100, 1.0);
  const StepBand plain = step_band(with_errors(1.0), t);
  const StepBand wide = step_band(projected, t);
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] > 3.0) {
      EXPECT_GT(wide.sigma[k], plain.sigma[k]) << t[k];
    }
  }
  ElementEstimate inside = with_errors(1.0);
  inside.projected_gain = ProjectedGain{{1.95, 2.05}, "within"};
  EXPECT_NEAR(step_band(inside, {400.0}).sigma[0], 0.05, 1e-6);
}

// GIVEN a 2×2 plant of form (6.1.1) under uncorrelated PRBS, noise variance 0.05 (seeded)
// WHEN identified THEN every element's true step response lies within its ±2σ band at
// (nearly) every minute, and the band is not trivially wide (below 10 % of |K| settled).
TEST(StepBand, ContainsTheTrueResponseInASeededIdentification) {
  const std::vector<ElementModel> truth = {
      {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  Eigen::MatrixXd Y = testing::plant_outputs(truth, 2, 2, 1.0, U);
  testing::add_noise(Y, 0.05, 7);
  const IdentificationResult r = identify(U, Y, 1.0);
  const std::vector<double> t = minutes(200, 1.0);
  for (int o = 0; o < 2; ++o) {
    for (int i = 0; i < 2; ++i) {
      const ElementEstimate& e = r.model.element(o, i);
      SCOPED_TRACE("element (" + std::to_string(o + 1) + "," + std::to_string(i + 1) + ")");
      ASSERT_EQ(e.status, ElementStatus::identified) << e.reason;
      for (const int a : free_parameters(e.value.structure)) {  // the structure's parameters
        for (const int b : free_parameters(e.value.structure)) {
          if (e.at_bound[static_cast<std::size_t>(a)] == Bound::none &&
              e.at_bound[static_cast<std::size_t>(b)] == Bound::none) {
            ASSERT_TRUE(std::isfinite(e.covariance(a, b))) << a << ", " << b;
          }
        }
      }
      EXPECT_NEAR(e.covariance(kGain, kGain), e.std_error.gain * e.std_error.gain,
                  1e-12 * e.covariance(kGain, kGain));
      const StepBand band = step_band(e, t);
      const ElementModel& p = truth[static_cast<std::size_t>(o * 2 + i)];
      int inside = 0;
      for (std::size_t k = 0; k < t.size(); ++k) {
        if (std::abs(step_response(p, t[k]) - band.response[k]) <= 2.0 * band.sigma[k] + 1e-12)
          ++inside;
      }
      EXPECT_GE(inside, static_cast<int>(0.95 * static_cast<double>(t.size())))
          << inside << " of " << t.size();
      EXPECT_LT(band.sigma.back(), 0.1 * std::abs(p.gain));
      EXPECT_GT(band.sigma.back(), 0.0);
    }
  }
}

}  // namespace
}  // namespace excite::host
