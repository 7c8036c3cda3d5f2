// SPDX-License-Identifier: MIT
// Measurement noise: N(0, σ²) per output, seeded and reproducible.
#include "sim/lti/noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace excite::sim {
namespace {

constexpr int kSamples = 100'000;

TEST(MeasurementNoise, HasZeroMeanAndTheRequestedVariancePerOutput) {
  const std::vector<double> variance = {0.03, 1.5};
  MeasurementNoise noise(variance, 42);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(kSamples, 2);
  noise.add(y);
  for (Eigen::Index i = 0; i < 2; ++i) {
    const double v = variance[static_cast<std::size_t>(i)];
    const double mean = y.col(i).mean();
    const double var = (y.col(i).array() - mean).square().sum() / (kSamples - 1);
    // Standard errors: √(v/N) for the mean, v·√(2/N) for the variance; allow 5 of them.
    EXPECT_NEAR(mean, 0.0, 5.0 * std::sqrt(v / kSamples)) << "output " << i;
    EXPECT_NEAR(var, v, 5.0 * v * std::sqrt(2.0 / kSamples)) << "output " << i;
  }
  // The outputs are independent of each other.
  const double corr = (y.col(0).array() * y.col(1).array()).mean() / std::sqrt(0.03 * 1.5);
  EXPECT_NEAR(corr, 0.0, 5.0 / std::sqrt(kSamples));
}

TEST(MeasurementNoise, TailsAreGaussian) {
  GaussianSource g(7);
  int beyond_two = 0;
  for (int k = 0; k < kSamples; ++k) beyond_two += std::abs(g.next()) > 2.0 ? 1 : 0;
  // P(|z| > 2) = 0.0455; binomial standard error ≈ 0.00066.
  EXPECT_NEAR(beyond_two / static_cast<double>(kSamples), 0.0455, 0.0033);
}

TEST(MeasurementNoise, SameSeedGivesTheSameSequence) {
  MeasurementNoise a(4, 0.03, 2024);
  MeasurementNoise b(4, 0.03, 2024);
  Eigen::MatrixXd ya = Eigen::MatrixXd::Zero(1000, 4);
  a.add(ya);
  // Sample by sample gives the same numbers as the whole matrix.
  for (Eigen::Index k = 0; k < 1000; ++k) {
    double row[4] = {0, 0, 0, 0};
    b.add(row);
    for (Eigen::Index i = 0; i < 4; ++i) ASSERT_EQ(row[i], ya(k, i));
  }
}

TEST(MeasurementNoise, DifferentSeedsGiveDifferentSequences) {
  MeasurementNoise a(1, 1.0, 1);
  MeasurementNoise b(1, 1.0, 2);
  Eigen::MatrixXd ya = Eigen::MatrixXd::Zero(100, 1);
  Eigen::MatrixXd yb = Eigen::MatrixXd::Zero(100, 1);
  a.add(ya);
  b.add(yb);
  int equal = 0;
  for (Eigen::Index k = 0; k < 100; ++k) equal += ya(k, 0) == yb(k, 0) ? 1 : 0;
  EXPECT_EQ(equal, 0);
}

TEST(MeasurementNoise, ZeroVarianceAddsNothing) {
  MeasurementNoise n(std::vector<double>{0.0, 0.03}, 5);
  double y[2] = {1.0, 1.0};
  n.add(y);
  EXPECT_EQ(y[0], 1.0);
  EXPECT_NE(y[1], 1.0);
}

TEST(MeasurementNoise, RefusesNegativeOrNonFiniteVariance) {
  try {
    MeasurementNoise bad(std::vector<double>{0.03, -0.1}, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("output 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MeasurementNoise(2, std::nan(""), 1), std::invalid_argument);
  MeasurementNoise ok(2, 0.03, 1);
  Eigen::MatrixXd wrong = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(ok.add(wrong), std::invalid_argument);
}

}  // namespace
}  // namespace excite::sim
