// SPDX-License-Identifier: MIT
// The coloured output disturbance (sim/lti/disturbance.hpp): first-order filtered noise of a
// given stationary std and time constant, deterministic by seed.
#include "sim/lti/disturbance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace excite::sim {
namespace {

std::vector<double> series(double std_dev, double tau, std::uint64_t seed, int n) {
  ColouredDisturbance d(1, std_dev, tau, 1.0, seed);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) {
    double y = 0.0;
    d.add(std::span<double>(&y, 1));
    x = y;
  }
  return v;
}

TEST(ColouredDisturbance, HasItsStationaryStdAndTheFirstOrderAutocorrelation) {
  // τ = 20 samples: a = exp(−1/20) = 0.9512; 200 000 samples ≈ 5 000 correlation times, so
  // the sample std and lag-1/lag-20 correlations are within ≈ 2 % of their values.
  const std::vector<double> v = series(0.3, 20.0, 11, 200'000);
  double s2 = 0.0, c1 = 0.0, c20 = 0.0;
  for (std::size_t k = 1000; k < v.size(); ++k) {
    s2 += v[k] * v[k];
    c1 += v[k] * v[k - 1];
    c20 += v[k] * v[k - 20];
  }
  EXPECT_NEAR(std::sqrt(s2 / static_cast<double>(v.size() - 1000)), 0.3, 0.3 * 0.05);
  EXPECT_NEAR(c1 / s2, std::exp(-1.0 / 20.0), 0.01);
  EXPECT_NEAR(c20 / s2, std::exp(-1.0), 0.05);
  EXPECT_EQ(v[0], 0.0);  // from rest
}

TEST(ColouredDisturbance, IsDeterministicBySeed) {
  EXPECT_EQ(series(0.1, 5.0, 3, 100), series(0.1, 5.0, 3, 100));
  EXPECT_NE(series(0.1, 5.0, 3, 100), series(0.1, 5.0, 4, 100));
  EXPECT_NE(disturbance_seed(3), 3U);  // another stream than the white noise of seed 3
}

TEST(ColouredDisturbance, RefusesBadValuesByName) {
  try {
    ColouredDisturbance(2, 0.1, 0.0, 1.0, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "disturbance tau_min = 0, expected a finite number of minutes > 0");
  }
  EXPECT_THROW(ColouredDisturbance(2, -1.0, 5.0, 1.0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace excite::sim
