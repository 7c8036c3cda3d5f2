// SPDX-License-Identifier: MIT
#include "host/identify/two_pole_element.hpp"

#include <gtest/gtest.h>

#include <random>

#include "reference_zoh.hpp"

namespace excite::host {
namespace {

Eigen::VectorXd random_levels(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  Eigen::VectorXd u(n);
  double v = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (k % 7 == 0) v = level(rng);
    u(k) = v;
  }
  return u;
}

Eigen::VectorXd discrete_response(const TwoPoleDelay& g, double T, const Eigen::VectorXd& u) {
  Eigen::VectorXd y(u.size());
  const auto n = static_cast<std::size_t>(u.size());
  simulate(discretise(g, T), {u.data(), n}, {y.data(), n});
  return y;
}

double relative_error(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

struct Case {
  const char* name;
  TwoPoleDelay g;
  double T;
};

class ZohDiscretisation : public ::testing::TestWithParam<Case> {};

// THEN the closed-form discretisation matches the matrix-exponential integration.
TEST_P(ZohDiscretisation, MatchesExactStateSpaceIntegration) {
  const Case c = GetParam();
  const Eigen::VectorXd u = random_levels(400, 3);
  const Eigen::VectorXd ref = testing::reference_response(c.g, c.T, u);
  EXPECT_LT(relative_error(discrete_response(c.g, c.T, u), ref), 1e-11) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Elements, ZohDiscretisation,
    ::testing::Values(Case{"distinct poles, fractional delay", {4.09, 1.3, 33.0, 8.3}, 1.0},
                      Case{"distinct poles, integer delay", {-2.0, 3.0, 12.0, 2.5}, 1.0},
                      Case{"double pole", {-0.05, 6.0, 34.5, 34.5}, 1.0},
                      Case{"first order", {1.53, 3.8, 48.0, 0.0}, 1.0},
                      Case{"first order, second slot", {1.53, 3.8, 0.0, 48.0}, 1.0},
                      Case{"pure gain, fractional delay", {2.0, 2.4, 0.0, 0.0}, 1.0},
                      Case{"pure gain, integer delay", {2.0, 2.0, 0.0, 0.0}, 1.0},
                      Case{"no delay", {14.0, 0.0, 45.0, 4.0}, 1.0},
                      Case{"delay below one sample", {1.0, 0.3, 5.0, 1.0}, 2.0},
                      Case{"fast poles vs T", {1.0, 0.7, 0.05, 0.01}, 1.0}),
    [](const ::testing::TestParamInfo<Case>& p) { return "case" + std::to_string(p.index); });

TEST(ZohDiscretisation, NearlyEqualPolesAreContinuousWithTheDoublePole) {
  const Eigen::VectorXd u = random_levels(300, 5);
  const TwoPoleDelay equal{1.0, 1.5, 20.0, 20.0};
  const TwoPoleDelay near{1.0, 1.5, 20.0, 20.0 * (1.0 + 1e-9)};
  EXPECT_LT(relative_error(discrete_response(near, 1.0, u), discrete_response(equal, 1.0, u)),
            1e-8);
}

TEST(ZohDiscretisation, VanishingTimeConstantTendsToTheFirstOrderElement) {
  const Eigen::VectorXd u = random_levels(300, 7);
  const TwoPoleDelay first{3.0, 2.7, 15.0, 0.0};
  for (const double small : {1e-6, 1e-12, 1e-100}) {
    const TwoPoleDelay g{3.0, 2.7, 15.0, small};
    EXPECT_LT(relative_error(discrete_response(g, 1.0, u), discrete_response(first, 1.0, u)), 1e-5)
        << small;
  }
}

TEST(ZohDiscretisation, StaticGainIsK) {
  const DiscreteTwoPole c = discretise(TwoPoleDelay{-11.2, 2.6, 43.0, 6.5}, 1.0);
  const double dc = (c.b[0] + c.b[1] + c.b[2] + c.b[3]) / (1.0 + c.a1 + c.a2);
  EXPECT_NEAR(dc, -11.2, 1e-10);
  EXPECT_EQ(c.delay_samples, 2U);
}

TEST(StepResponse, ClosedFormValues) {
  // S(t) = K (1 − (a e^{−t/a} − b e^{−t/b}) / (a − b)) after the delay.
  const TwoPoleDelay g{2.0, 1.0, 10.0, 4.0};
  const double t = 7.0;
  const double expected =
      2.0 * (1.0 - (10.0 * std::exp(-6.0 / 10.0) - 4.0 * std::exp(-6.0 / 4.0)) / 6.0);
  EXPECT_NEAR(step_response(g, t), expected, 1e-14);
  EXPECT_EQ(step_response(g, 0.5), 0.0);
  // Double pole: K (1 − (1 + t/a) e^{−t/a}).
  const TwoPoleDelay d{2.0, 0.0, 5.0, 5.0};
  EXPECT_NEAR(step_response(d, 3.0), 2.0 * (1.0 - 1.6 * std::exp(-0.6)), 1e-14);
}

}  // namespace
}  // namespace excite::host
