// SPDX-License-Identifier: MIT
#include "host/identify/element.hpp"

#include <gtest/gtest.h>

#include <random>

#include "reference_zoh.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

Eigen::VectorXd discrete_response(const ElementModel& g, double T, const Eigen::VectorXd& u) {
  Eigen::VectorXd y(u.size());
  const auto n = static_cast<std::size_t>(u.size());
  simulate(discretise(g, T), {u.data(), n}, {y.data(), n});
  return y;
}

double relative_error(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

struct ElementCase {
  const char* name;
  ElementModel g;
  double T;
};

class ZohDiscretisation : public ::testing::TestWithParam<ElementCase> {};

// The discretisation identification uses (sim/lti via host::discretise) matches the
// sub-interval matrix-exponential integration of the oracle.
TEST_P(ZohDiscretisation, MatchesExactStateSpaceIntegration) {
  const ElementCase c = GetParam();
  const Eigen::VectorXd u = testing::random_levels(400, 3);
  const Eigen::VectorXd ref = testing::reference_response(c.g, c.T, u);
  EXPECT_LT(relative_error(discrete_response(c.g, c.T, u), ref), 1e-11) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Elements, ZohDiscretisation,
    ::testing::Values(ElementCase{"distinct poles, fractional delay", {4.09, 1.3, 33.0, 8.3}, 1.0},
                      ElementCase{"distinct poles, integer delay", {-2.0, 3.0, 12.0, 2.5}, 1.0},
                      ElementCase{"double pole", {-0.05, 6.0, 34.5, 34.5}, 1.0},
                      ElementCase{"first order", {1.53, 3.8, 48.0, 0.0}, 1.0},
                      ElementCase{"first order, second slot", {1.53, 3.8, 0.0, 48.0}, 1.0},
                      ElementCase{"pure gain, fractional delay", {2.0, 2.4, 0.0, 0.0}, 1.0},
                      ElementCase{"pure gain, integer delay", {2.0, 2.0, 0.0, 0.0}, 1.0},
                      ElementCase{"no delay", {14.0, 0.0, 45.0, 4.0}, 1.0},
                      ElementCase{"delay below one sample", {1.0, 0.3, 5.0, 1.0}, 2.0},
                      ElementCase{"fast poles vs T", {1.0, 0.7, 0.05, 0.01}, 1.0}),
    [](const ::testing::TestParamInfo<ElementCase>& p) {
      return "case" + std::to_string(p.index);
    });

TEST(ZohDiscretisation, NearlyEqualPolesAreContinuousWithTheDoublePole) {
  const Eigen::VectorXd u = testing::random_levels(300, 5);
  const ElementModel equal{1.0, 1.5, 20.0, 20.0};
  const ElementModel near{1.0, 1.5, 20.0, 20.0 * (1.0 + 1e-9)};
  EXPECT_LT(relative_error(discrete_response(near, 1.0, u), discrete_response(equal, 1.0, u)),
            1e-8);
}

TEST(ZohDiscretisation, VanishingTimeConstantTendsToTheFirstOrderElement) {
  const Eigen::VectorXd u = testing::random_levels(300, 7);
  const ElementModel first{3.0, 2.7, 15.0, 0.0};
  for (const double small : {1e-6, 1e-12, 1e-100}) {
    const ElementModel g{3.0, 2.7, 15.0, small};
    EXPECT_LT(relative_error(discrete_response(g, 1.0, u), discrete_response(first, 1.0, u)), 1e-5)
        << small;
  }
}

TEST(ZohDiscretisation, StaticGainIsKAndDelayIsWholeSamples) {
  const sim::DiscreteTerm c = discretise(ElementModel{-11.2, 2.6, 43.0, 6.5}, 1.0);
  EXPECT_NEAR(c.static_gain(), -11.2, 1e-10);
  // 2.6 min = 2 whole samples + a fraction, and a strictly proper element adds one more.
  EXPECT_EQ(c.delay_samples, 3);
}

// The taps by lag reproduce the simulation: y = B(q)/D(q) u from lag_taps and the
// all-pole filter equals simulate().
TEST(LagTaps, ReproduceTheSimulation) {
  const ElementModel g{1.7, 4.35, 25.0, 7.0};
  const Eigen::VectorXd u = testing::random_levels(300, 9);
  const LagTaps t = lag_taps(g, 1.0, 3);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(u.size());
  for (std::size_t m = 0; m < kLagWindow; ++m) {
    const auto lag = static_cast<Eigen::Index>(3 + m);
    y.tail(u.size() - lag) += t.b[m] * u.head(u.size() - lag);
  }
  all_pole_filter(t.a, {y.data(), static_cast<std::size_t>(y.size())});
  EXPECT_LT(relative_error(y, discrete_response(g, 1.0, u)), 1e-12);
}

}  // namespace
}  // namespace excite::host
