// SPDX-License-Identifier: MIT
// The discrete plant: stepping and whole-experiment simulation agree, delays route inputs
// exactly, stepping does not allocate, and bad input is refused.
#include "sim/lti/discrete_plant.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>

#include "sim/lti/plant_toml.hpp"

// Counts every global allocation, so a test can prove a code path allocates nothing.
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements pair malloc with free by design; GCC cannot see that when it inlines them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace excite::sim {
namespace {

// Case-study-like 2×3 plant with every element form: delays (whole and fractional), zero,
// quadratic, repeated pole, sum, static gain with delay, a zero element.
TransferMatrix mixed_plant() {
  return TransferMatrix::parse(
      {{"4.09 e^-1.3s / ((33s+1)(8.3s+1))", "14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))",
        "-0.56 e^-1s"},
       {"-87.8/(194s+1) + 1.4 e^-2.5s/(15s+1)", "0", "-0.05 e^-6s / (34.5s+1)^2"}});
}

Eigen::MatrixXd pseudo_random_inputs(Eigen::Index n, Eigen::Index m) {
  Eigen::MatrixXd u(n, m);
  std::uint64_t x = 88172645463325252ULL;
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index j = 0; j < m; ++j) {
      x ^= x << 13U;
      x ^= x >> 7U;
      x ^= x << 17U;
      u(k, j) = (x & 1U) != 0 ? 1.0 : -1.0;
    }
  }
  return u;
}

TEST(DiscretePlant, SteppingEqualsWholeExperimentSimulation) {
  DiscretePlant plant(mixed_plant(), 1.0);
  const Eigen::MatrixXd u = pseudo_random_inputs(500, 3);
  const Eigen::MatrixXd y = plant.simulate(u);
  ASSERT_EQ(y.rows(), 500);
  ASSERT_EQ(y.cols(), 2);
  double uk[3];
  double yk[2];
  for (Eigen::Index k = 0; k < u.rows(); ++k) {
    for (Eigen::Index j = 0; j < 3; ++j) uk[j] = u(k, j);
    plant.step(uk, yk);
    ASSERT_NEAR(yk[0], y(k, 0), 1e-12) << k;
    ASSERT_NEAR(yk[1], y(k, 1), 1e-12) << k;
  }
  EXPECT_GT(y.cwiseAbs().maxCoeff(), 1.0);  // the comparison is not between zeros
}

TEST(DiscretePlant, ResetRestartsFromZeroState) {
  DiscretePlant plant(mixed_plant(), 1.0);
  const double u[3] = {1.0, -1.0, 0.5};
  double first[2];
  double again[2];
  for (int k = 0; k < 10; ++k) plant.step(u, first);
  plant.reset();
  for (int k = 0; k < 10; ++k) plant.step(u, again);
  EXPECT_EQ(first[0], again[0]);
  EXPECT_EQ(first[1], again[1]);
}

TEST(DiscretePlant, StaticGainOfTheDiscretePlantIsG0) {
  const TransferMatrix g = mixed_plant();
  const DiscretePlant plant(g, 0.7);
  EXPECT_LT((plant.static_gain() - g.static_gain()).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(DiscretePlant, LongStepSettlesAtG0) {
  const TransferMatrix g = mixed_plant();
  const DiscretePlant plant(g, 1.0);
  const Eigen::MatrixXd y = plant.simulate(Eigen::MatrixXd::Constant(6000, 3, 1.0));
  const Eigen::VectorXd expected = g.static_gain().rowwise().sum();
  EXPECT_NEAR(y(5999, 0), expected(0), 1e-9);
  EXPECT_NEAR(y(5999, 1), expected(1), 1e-9);
}

TEST(DiscretePlant, DelayShiftsTheInputByWholeSamples) {
  const DiscretePlant plant(TransferMatrix::parse({{"2 e^-3s"}}), 1.0);
  const Eigen::MatrixXd u = pseudo_random_inputs(50, 1);
  const Eigen::MatrixXd y = plant.simulate(u);
  for (Eigen::Index k = 0; k < 50; ++k) {
    EXPECT_EQ(y(k, 0), k < 3 ? 0.0 : 2.0 * u(k - 3, 0)) << k;
  }
}

TEST(DiscretePlant, DelayLongerThanTheExperimentGivesZeros) {
  const DiscretePlant plant(TransferMatrix::parse({{"1 e^-100s / (2s+1)"}}), 1.0);
  EXPECT_EQ(plant.simulate(Eigen::MatrixXd::Ones(20, 1)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DiscretePlant, SteppingDoesNotAllocate) {
  DiscretePlant plant(mixed_plant(), 1.0);
  const double u[3] = {1.0, -1.0, 0.5};
  double y[2];
  const long before = g_allocations.load();
  for (int k = 0; k < 1000; ++k) plant.step(u, y);
  plant.reset();
  EXPECT_EQ(g_allocations.load() - before, 0);
}

TEST(DiscretePlant, RefusesNonFiniteInputs) {
  DiscretePlant plant(mixed_plant(), 1.0);
  const double u[3] = {1.0, std::nan(""), 0.0};
  double y[2];
  EXPECT_THROW(plant.step(u, y), std::invalid_argument);
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(10, 3);
  big(4, 2) = INFINITY;
  try {
    (void)plant.simulate(big);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("U(4, 2)"), std::string::npos) << e.what();
  }
}

TEST(DiscretePlant, RefusesTheWrongInputCount) {
  const DiscretePlant plant(mixed_plant(), 1.0);
  EXPECT_THROW((void)plant.simulate(Eigen::MatrixXd::Zero(10, 2)), std::invalid_argument);
}

TEST(DiscretePlant, RefusesBadSampleTime) {
  EXPECT_THROW(DiscretePlant(mixed_plant(), 0.0), std::invalid_argument);
  EXPECT_THROW(DiscretePlant(mixed_plant(), -1.0), std::invalid_argument);
}

TEST(TransferMatrix, FrequencyResponseIsTheElementwiseResponse) {
  const TransferMatrix g = mixed_plant();
  const Eigen::MatrixXcd h = g.frequency_response(0.05);
  const std::complex<double> s{0.0, 0.05};
  EXPECT_NEAR(std::abs(h(0, 2) - (-0.56 * std::exp(-s))), 0.0, 1e-14);
  EXPECT_EQ(h(1, 1), std::complex<double>(0.0, 0.0));
  EXPECT_NEAR(std::abs(g.frequency_response(0.0)(1, 0) - g.static_gain()(1, 0)), 0.0, 1e-12);
  EXPECT_LT((g.frequency_response(-0.05) - h.conjugate()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_THROW((void)g.frequency_response(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace excite::sim
