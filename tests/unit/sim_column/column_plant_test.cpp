// SPDX-License-Identifier: MIT
// The plant contract of sim/column/column_plant.hpp: deviations in and out, ZOH sampling,
// stepping equal to simulating, and clear errors for bad input.
#include "sim/column/column_plant.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::sim::column {
namespace {

using ::testing::HasSubstr;

Eigen::MatrixXd small_inputs(Eigen::Index n) {
  Eigen::MatrixXd u(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    u(k, 0) = (k % 3 == 0 ? 1.0 : -1.0) * 0.01;
    u(k, 1) = (k % 2 == 0 ? 1.0 : -1.0) * 0.01;
  }
  return u;
}

class PlantContract : public ::testing::Test {
 protected:
  ColumnPlant plant_ = ColumnPlant::cola_a();
};

TEST_F(PlantContract, DescribesItselfAsATwoByTwoPlant) {
  EXPECT_EQ(plant_.name(), "colaA");
  EXPECT_EQ(plant_.inputs(), 2);
  EXPECT_EQ(plant_.outputs(), 2);
  EXPECT_EQ(plant_.input_names(), (std::vector<std::string>{"L", "V"}));
  EXPECT_EQ(plant_.output_names(), (std::vector<std::string>{"xD", "xB"}));
}

TEST_F(PlantContract, ZeroInputsKeepTheNominalSteadyState) {
  const Eigen::MatrixXd y = plant_.simulate(Eigen::MatrixXd::Zero(30, 2), 1.0);
  EXPECT_LT(y.lpNorm<Eigen::Infinity>(), 1e-9);
}

// Row k is sampled at the start of interval k: it cannot see U row k or later.
TEST_F(PlantContract, OutputsAreSampledBeforeTheInputOfTheSameInterval) {
  const Eigen::MatrixXd u = small_inputs(12);
  const Eigen::MatrixXd y = plant_.simulate(u, 1.0);
  EXPECT_EQ(y.row(0).lpNorm<Eigen::Infinity>(), 0.0);
  Eigen::MatrixXd u2 = u;
  u2.row(7) *= -1.0;
  plant_.reset();
  const Eigen::MatrixXd y2 = plant_.simulate(u2, 1.0);
  EXPECT_LT((y.topRows(8) - y2.topRows(8)).lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_GT((y.bottomRows(4) - y2.bottomRows(4)).lpNorm<Eigen::Infinity>(), 1e-6);
}

TEST_F(PlantContract, SimulationContinuesFromWhereItStopped) {
  const Eigen::MatrixXd u = small_inputs(20);
  const Eigen::MatrixXd whole = plant_.simulate(u, 1.0);
  plant_.reset();
  const Eigen::MatrixXd first = plant_.simulate(u.topRows(9), 1.0);
  const Eigen::MatrixXd second = plant_.simulate(u.bottomRows(11), 1.0);
  EXPECT_LT((whole.topRows(9) - first).lpNorm<Eigen::Infinity>(), 1e-8);
  EXPECT_LT((whole.bottomRows(11) - second).lpNorm<Eigen::Infinity>(), 1e-8);
}

TEST_F(PlantContract, SteppingEqualsSimulating) {
  const Eigen::MatrixXd u = small_inputs(15);
  const Eigen::MatrixXd y = plant_.simulate(u, 0.5);
  plant_.reset();
  plant_.set_sample_time_min(0.5);
  for (Eigen::Index k = 0; k < u.rows(); ++k) {
    const double in[2] = {u(k, 0), u(k, 1)};
    double out[2] = {0.0, 0.0};
    plant_.step(in, out);
    EXPECT_DOUBLE_EQ(out[0], y(k, 0));
    EXPECT_DOUBLE_EQ(out[1], y(k, 1));
  }
}

// Small steps in the weak direction (L and V together) and the strong one (apart) move
// the outputs by G(0) times the step after the slow mode has settled.
TEST_F(PlantContract, LongRunFollowsTheStaticGainForSmallSteps) {
  const Eigen::MatrixXd g = plant_.static_gain();
  for (const Eigen::Vector2d& du : {Eigen::Vector2d(1e-4, 1e-4), Eigen::Vector2d(1e-4, -1e-4)}) {
    plant_.reset();
    Eigen::MatrixXd u(16, 2);
    u.rowwise() = du.transpose();
    plant_.simulate(u, 150.0);
    const Eigen::Vector2d y = plant_.simulate(Eigen::MatrixXd(u.topRows(1)), 1.0).row(0);
    const Eigen::Vector2d expected = g * du;
    EXPECT_NEAR(y[0], expected[0], 0.03 * expected.norm());
    EXPECT_NEAR(y[1], expected[1], 0.03 * expected.norm());
  }
}

TEST_F(PlantContract, RejectsNonFiniteInputsNamingTheSample) {
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(5, 2);
  u(3, 0) = std::numeric_limits<double>::quiet_NaN();
  try {
    plant_.simulate(u, 1.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("input L"));
    EXPECT_THAT(e.what(), HasSubstr("sample 3"));
  }
  EXPECT_EQ(plant_.state(), plant_.nominal_state()) << "nothing half-simulated";
  const double in[2] = {0.0, std::numeric_limits<double>::infinity()};
  double out[2];
  EXPECT_THROW(plant_.step(in, out), std::invalid_argument);
}

TEST_F(PlantContract, RejectsNegativeAbsoluteFlows) {
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(1, 2);
  u(0, 0) = -3.0;  // L = 2.706 − 3 < 0
  try {
    plant_.simulate(u, 1.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("reflux L"));
  }
}

// V cut to 0.2 kmol/min with L unchanged: the reflux drum drains (D would have to be
// negative), which the plant reports instead of integrating on.
TEST_F(PlantContract, RejectsInputsThatDrainAStage) {
  const Eigen::MatrixXd u = (Eigen::MatrixXd(1, 2) << 0.0, -3.0).finished();
  try {
    plant_.simulate(u, 5.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("stage"));
  }
  EXPECT_EQ(plant_.state(), plant_.nominal_state()) << "the failing interval is not committed";
}

TEST_F(PlantContract, RejectsMalformedCallsAndDisturbances) {
  EXPECT_THROW(plant_.simulate(Eigen::MatrixXd::Zero(3, 3), 1.0), std::invalid_argument);
  EXPECT_THROW(plant_.simulate(Eigen::MatrixXd::Zero(3, 2), 0.0), std::invalid_argument);
  EXPECT_THROW(plant_.set_sample_time_min(-1.0), std::invalid_argument);
  EXPECT_THROW(plant_.set_disturbances(std::nan(""), 0.5), std::invalid_argument);
  EXPECT_THROW(plant_.set_disturbances(1.0, 1.5), std::invalid_argument);
  EXPECT_THROW(plant_.set_disturbances(-0.1, 0.5), std::invalid_argument);
  try {
    ColumnPlant::by_name("colaB");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("colaA"));
  }
}

TEST_F(PlantContract, FeedCompositionDisturbanceMovesBothProductsTheSameWay) {
  plant_.set_disturbances(1.0, 0.51);
  const Eigen::MatrixXd y = plant_.simulate(Eigen::MatrixXd::Zero(11, 2), 10.0);
  EXPECT_GT(y(10, 0), 0.0);
  EXPECT_GT(y(10, 1), 0.0);
}

}  // namespace
}  // namespace excite::sim::column
