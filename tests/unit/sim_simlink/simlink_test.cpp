// SPDX-License-Identifier: MIT
// The in-process link drives any sim::Plant through its live interface: what a PLC would
// read equals the plant's batch simulation plus its operating point, for a column and a
// linear plant; a plant's refusal is a peer_error named in detail(); the cyclic calls
// allocate nothing, with a column too.
#include "sim/simlink/simlink_field_bus.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "counting_malloc.hpp"
#include "counting_new.hpp"
#include "excite/hal/virtual_clock.hpp"
#include "sim/library/library.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::simlink {
namespace {

using hal::StatusCode;
using ::testing::HasSubstr;

Eigen::MatrixXd moves(Eigen::Index n, int inputs, double a) {
  Eigen::MatrixXd u(n, inputs);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int j = 0; j < inputs; ++j) u(k, j) = ((k / (2 + j)) % 2 == 0 ? a : -a);
  }
  return u;
}

// Writes u0 + du(k), reads, returns the absolute outputs of each exchange.
Eigen::MatrixXd exchange_all(SimLinkFieldBus& bus, const Eigen::VectorXd& u0,
                             const Eigen::MatrixXd& du) {
  Eigen::MatrixXd y(du.rows(), static_cast<Eigen::Index>(bus.value_count()));
  std::vector<double> sp(bus.setpoint_count());
  std::vector<double> values(bus.value_count());
  for (Eigen::Index k = 0; k < du.rows(); ++k) {
    for (std::size_t j = 0; j < sp.size(); ++j) {
      sp[j] = u0[static_cast<Eigen::Index>(j)] + du(k, static_cast<Eigen::Index>(j));
    }
    EXPECT_EQ(bus.write(sp, static_cast<std::uint16_t>(k)), StatusCode::ok) << bus.detail();
    EXPECT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
    for (std::size_t i = 0; i < values.size(); ++i) y(k, static_cast<Eigen::Index>(i)) = values[i];
  }
  return y;
}

TEST(SimLink, DrivesAColumnAtItsOwnOperatingPoint) {
  hal::VirtualClock clock;
  SimLinkConfig config;  // baselines empty: the column's own (absolute flows, compositions)
  config.exchange_time = std::chrono::milliseconds(2);
  SimLinkFieldBus bus(make_plant("colaA"), 1.0, config, &clock);
  auto reference = make_plant("colaA");
  const Eigen::VectorXd u0 = reference->input_baseline();
  const Eigen::VectorXd y0 = reference->output_baseline();
  const Eigen::MatrixXd du = moves(60, 2, 0.01);
  const Eigen::MatrixXd read = exchange_all(bus, u0, du);
  const Eigen::MatrixXd batch = reference->simulate(du, 1.0);
  // Outputs: y0 + dy, the same integration as simulate() (sim/plants step_test: equal).
  EXPECT_LE((read.leftCols(2).rowwise() - y0.transpose() - batch).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_GT(batch.lpNorm<Eigen::Infinity>(), 1e-5) << "the column must respond";
  // Readbacks: the absolute setpoints held.
  EXPECT_LE((read.middleCols(2, 2).rowwise() - u0.transpose() - du).lpNorm<Eigen::Infinity>(),
            1e-12);
  EXPECT_EQ(bus.samples(), 60U);
  EXPECT_EQ(clock.now(), std::chrono::milliseconds(2 * 2 * 60));
}

TEST(SimLink, DrivesALinearPlantGivenByItsTransferMatrix) {
  SimLinkConfig config;
  config.input_baseline = {50, 60, 70, 80};
  config.output_baseline = {0.9, 0.1, 0.5, 0.3};
  SimLinkFieldBus bus(library_plant("alatiqi4x4"), 1.0, config);
  const Eigen::MatrixXd du = moves(200, 4, 1.0);
  const Eigen::MatrixXd read = exchange_all(bus, Eigen::Vector4d(50, 60, 70, 80), du);
  const Eigen::MatrixXd batch = make_plant("alatiqi4x4")->simulate(du, 1.0);
  const Eigen::RowVector4d y0(0.9, 0.1, 0.5, 0.3);
  EXPECT_LE((read.leftCols(4).rowwise() - y0 - batch).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(SimLink, APlantRefusingASampleIsAPeerErrorNamedInDetail) {
  SimLinkFieldBus bus(make_plant("colaA"), 1.0, SimLinkConfig{});
  const std::vector<double> negative_reflux = {-1.0, 3.2};  // absolute kmol/min
  EXPECT_EQ(bus.write(negative_reflux, 1), StatusCode::peer_error);
  EXPECT_THAT(bus.detail(), HasSubstr("reflux L = -1"));
  EXPECT_EQ(bus.plant_errors(), 1U);
  EXPECT_EQ(bus.samples(), 0U) << "the refused sample did not happen";
  const Eigen::VectorXd u0 = bus.plant().input_baseline();
  const std::vector<double> nominal = {u0[0], u0[1]};
  EXPECT_EQ(bus.write(nominal, 2), StatusCode::ok);
  EXPECT_EQ(bus.samples(), 1U);
}

TEST(SimLink, WrongBaselinesAndANullPlantAreRefusedByName) {
  SimLinkConfig config;
  config.input_baseline = {1.0, 2.0, 3.0};
  try {
    SimLinkFieldBus bus(make_plant("colaA"), 1.0, config);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("input_baseline has 3 values, expected 2"));
  }
  EXPECT_THROW(SimLinkFieldBus(std::unique_ptr<Plant>{}, 1.0, SimLinkConfig{}),
               std::invalid_argument);
  EXPECT_THROW(SimLinkFieldBus(make_plant("colaA"), 0.0, SimLinkConfig{}), std::invalid_argument);
}

TEST(SimLink, CyclicCallsWithAColumnAllocateNothing) {
  SimLinkFieldBus bus(make_plant("colaA"), 1.0, SimLinkConfig{});
  const Eigen::VectorXd u0 = bus.plant().input_baseline();
  std::vector<double> sp = {u0[0], u0[1]};
  std::vector<double> values(bus.value_count());
  const long n0 = excite::test::allocations();
  const long m0 = excite::test::mallocs();
  for (int k = 0; k < 300; ++k) {
    sp[0] = u0[0] + ((k / 2) % 2 == 0 ? 0.01 : -0.01);
    ASSERT_EQ(bus.write(sp, static_cast<std::uint16_t>(k)), StatusCode::ok);
    ASSERT_EQ(bus.read(values), StatusCode::ok);
  }
  EXPECT_EQ(excite::test::allocations() - n0, 0);
  if (excite::test::malloc_interposed()) {
    EXPECT_EQ(excite::test::mallocs() - m0, 0);
  }
}

}  // namespace
}  // namespace excite::sim::simlink
