// SPDX-License-Identifier: MIT
// Live stepping of a column (ColumnPlant::step): the work per sample is capped and counted,
// a sample over the cap is refused and not committed, and stepping then goes on exactly.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/column/column_plant.hpp"

namespace excite::sim::column {
namespace {

using ::testing::HasSubstr;

long attempts(const ColumnPlant& plant) {
  return plant.stats().accepted_steps + plant.stats().rejected_steps;
}

// Both inputs flip between ±0.01 kmol/min with different periods: every sample starts just
// after an input change on at least one input half the time, the integrator's worst case.
void input_at(long k, double* u) {
  u[0] = (k / 2) % 2 == 0 ? 0.01 : -0.01;
  u[1] = (k / 3) % 2 == 0 ? 0.01 : -0.01;
}

TEST(ColumnStep, EverySampleStaysWithinTheWorkCap) {
  ColumnPlant plant = ColumnPlant::cola_a();
  ASSERT_EQ(plant.max_steps_per_sample(), ColumnPlant::kDefaultMaxStepsPerSample);
  plant.set_sample_time_min(1.0);
  long most = 0;
  for (long k = 0; k < 600; ++k) {
    double u[2], y[2];
    input_at(k, u);
    const long before = attempts(plant);
    plant.step(u, y);
    const long used = attempts(plant) - before;
    ASSERT_GE(used, 1) << "sample " << k;
    most = std::max(most, used);
  }
  EXPECT_LE(most, plant.max_steps_per_sample());
  // The default cap leaves a wide margin over what a case-study sample needs (README.md).
  EXPECT_LE(most * 10, plant.max_steps_per_sample()) << "most steps in one sample: " << most;
}

TEST(ColumnStep, ASampleOverTheCapIsRefusedAfterExactlyTheCapAndNotCommitted) {
  ColumnPlant plant = ColumnPlant::cola_a();
  ColumnPlant reference = ColumnPlant::cola_a();
  plant.set_sample_time_min(1.0);
  reference.set_sample_time_min(1.0);
  double u[2], y[2], y_ref[2];
  for (long k = 0; k < 5; ++k) {
    input_at(k, u);
    plant.step(u, y);
    reference.step(u, y_ref);
  }
  const Eigen::VectorXd state_before = plant.state();
  plant.set_max_steps_per_sample(2);  // a sample after an input change needs more than 2
  input_at(5, u);
  const long before = attempts(plant);
  try {
    plant.step(u, y);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("colaA: sample 5"));
    EXPECT_THAT(e.what(), HasSubstr("max_steps_per_sample = 2"));
  }
  EXPECT_EQ(attempts(plant) - before, 2) << "the cap bounds the work done before refusing";
  EXPECT_EQ((plant.state() - state_before).lpNorm<Eigen::Infinity>(), 0.0);
  // With the cap lifted again the same sample goes through and the trajectories agree.
  plant.set_max_steps_per_sample(ColumnPlant::kDefaultMaxStepsPerSample);
  for (long k = 5; k < 20; ++k) {
    input_at(k, u);
    plant.step(u, y);
    reference.step(u, y_ref);
    EXPECT_EQ(y[0], y_ref[0]) << "sample " << k;
    EXPECT_EQ(y[1], y_ref[1]) << "sample " << k;
  }
}

TEST(ColumnStep, TheCapMustBePositive) {
  ColumnPlant plant = ColumnPlant::cola_a();
  try {
    plant.set_max_steps_per_sample(0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("max_steps_per_sample = 0"));
  }
}

}  // namespace
}  // namespace excite::sim::column
