// SPDX-License-Identifier: MIT
// The live interface of sim::Plant (sim/plants/plant.hpp): reset(T) then step(du, dy) once per
// sample gives the batch simulate() trajectory, for every plant make_plant knows; bad
// arguments are refused by name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/plants/plant.hpp"

namespace excite::sim {
namespace {

using ::testing::HasSubstr;

// The columns move by a few hundredths (colaA) or tenths of a mol/min (pilot15) at most
// (host/design case studies); the linear models are unit-free.
double amplitude_of(const std::string& name) {
  if (name == "colaA") return 0.01;
  if (name == "pilot15") return 0.0004;
  return 1.0;
}

// A deterministic ±a pattern per input with mixed periods, so every input moves often and
// the inputs are not collinear.
Eigen::MatrixXd test_inputs(Eigen::Index n, int inputs, double a) {
  Eigen::MatrixXd u(n, inputs);
  for (Eigen::Index k = 0; k < n; ++k) {
    for (int j = 0; j < inputs; ++j) {
      const Eigen::Index period = 2 + j;
      u(k, j) = ((k / period + j) % 2 == 0 ? a : -a) * (k % 7 == 3 ? 0.5 : 1.0);
    }
  }
  return u;
}

Eigen::MatrixXd step_through(Plant& plant, const Eigen::MatrixXd& u) {
  Eigen::MatrixXd y(u.rows(), plant.outputs());
  std::vector<double> du(static_cast<std::size_t>(plant.inputs()));
  std::vector<double> dy(static_cast<std::size_t>(plant.outputs()));
  for (Eigen::Index k = 0; k < u.rows(); ++k) {
    for (int j = 0; j < plant.inputs(); ++j) du[static_cast<std::size_t>(j)] = u(k, j);
    plant.step(du, dy);
    for (int i = 0; i < plant.outputs(); ++i) y(k, i) = dy[static_cast<std::size_t>(i)];
  }
  return y;
}

// Linear plants: step() and simulate() run the same difference equations in the same order
// (sim/lti/discrete_plant.cpp), so they agree to rounding: 1e-12 relative to the response.
// Columns: the live copy integrates from the same steady state with the same integrator,
// tolerances and step-size memory and the same held inputs, so the arithmetic is the same
// operation for operation; any difference would be a bug, not integration error. 1e-12 mole
// fraction is 1e-5 of the integration tolerance (1e-7) and far below any response (≥ 1e-6).
constexpr double kLinearTolerance = 1e-12;
constexpr double kColumnTolerance = 1e-12;

double tolerance_of(const std::string& name, const Eigen::MatrixXd& y) {
  if (name == "colaA" || name == "pilot15") return kColumnTolerance;
  return kLinearTolerance * std::max(1.0, y.lpNorm<Eigen::Infinity>());
}

Eigen::Index samples_of(const std::string& name) {
  return name == "pilot15" ? 40 : name == "colaA" ? 120 : 400;
}

class EveryPlant : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryPlant, SteppingEqualsTheBatchSimulation) {
  const std::string name = GetParam();
  auto plant = make_plant(name);
  for (double t : {1.0, 0.5}) {
    if (t != 1.0 && (name == "colaA" || name == "pilot15")) continue;  // one T is enough there
    const Eigen::MatrixXd u = test_inputs(samples_of(name), plant->inputs(), amplitude_of(name));
    const Eigen::MatrixXd batch = plant->simulate(u, t);
    plant->reset(t);
    const Eigen::MatrixXd live = step_through(*plant, u);
    ASSERT_GT(batch.lpNorm<Eigen::Infinity>(), 0.0) << "the test inputs must move " << name;
    EXPECT_LE((live - batch).lpNorm<Eigen::Infinity>(), tolerance_of(name, batch))
        << name << " at T = " << t << " min";
  }
}

TEST_P(EveryPlant, ResetReturnsToRest) {
  const std::string name = GetParam();
  auto plant = make_plant(name);
  const Eigen::MatrixXd u = test_inputs(30, plant->inputs(), amplitude_of(name));
  plant->reset(1.0);
  const Eigen::MatrixXd first = step_through(*plant, u);
  plant->reset(1.0);
  const Eigen::MatrixXd again = step_through(*plant, u);
  EXPECT_EQ(first.row(0).lpNorm<Eigen::Infinity>(), 0.0) << "dy(0) is sampled at rest";
  EXPECT_LE((first - again).lpNorm<Eigen::Infinity>(), tolerance_of(name, first));
}

// A batch simulation between two steps does not disturb the live state.
TEST_P(EveryPlant, SimulateLeavesTheLiveSimulationAlone) {
  const std::string name = GetParam();
  auto plant = make_plant(name);
  const Eigen::MatrixXd u = test_inputs(20, plant->inputs(), amplitude_of(name));
  plant->reset(1.0);
  const Eigen::MatrixXd straight = step_through(*plant, u);
  plant->reset(1.0);
  Eigen::MatrixXd split(u.rows(), plant->outputs());
  split.topRows(10) = step_through(*plant, u.topRows(10));
  (void)plant->simulate(-u, 2.0);
  split.bottomRows(10) = step_through(*plant, u.bottomRows(10));
  EXPECT_LE((split - straight).lpNorm<Eigen::Infinity>(), tolerance_of(name, straight));
}

TEST_P(EveryPlant, BaselinesHaveOneValuePerSignal) {
  auto plant = make_plant(GetParam());
  EXPECT_EQ(plant->input_baseline().size(), plant->inputs());
  EXPECT_EQ(plant->output_baseline().size(), plant->outputs());
}

INSTANTIATE_TEST_SUITE_P(PlantNames, EveryPlant, ::testing::ValuesIn(plant_names()),
                         [](const auto& param_info) { return param_info.param; });

TEST(PlantFile, SteppingEqualsTheBatchSimulation) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("excite_step_test_" + std::to_string(::getpid()) + ".toml");
  {
    std::ofstream out(file);
    out << R"toml(
name = "demo"
time_unit = "min"
inputs = ["reflux", "boilup"]
outputs = ["xD", "xB"]
G = [
  ["12.8 e^-1s / (16.7s+1)", -18.9],
  ["6.6 e^-7s / (10.9s+1)",  "87.8/(194s+1) + 1.4/(15s+1)"],
]
)toml";
  }
  auto plant = make_plant(file.string());
  std::filesystem::remove(file);
  const Eigen::MatrixXd u = test_inputs(300, 2, 1.0);
  const Eigen::MatrixXd batch = plant->simulate(u, 1.0);
  plant->reset(1.0);
  const Eigen::MatrixXd live = step_through(*plant, u);
  EXPECT_LE((live - batch).lpNorm<Eigen::Infinity>(), tolerance_of("demo", batch));
}

TEST(Baselines, LinearPlantsAreZeroAndColumnsAreTheirNominalCompositions) {
  EXPECT_EQ(make_plant("alatiqi4x4")->output_baseline().lpNorm<Eigen::Infinity>(), 0.0);
  const Eigen::VectorXd y0 = make_plant("colaA")->output_baseline();
  EXPECT_NEAR(y0[0], 0.99, 1e-6);
  EXPECT_NEAR(y0[1], 0.01, 1e-6);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

class StepErrors : public ::testing::TestWithParam<std::string> {};

TEST_P(StepErrors, StepBeforeResetIsRefused) {
  auto plant = make_plant(GetParam());
  std::vector<double> du(static_cast<std::size_t>(plant->inputs()), 0.0);
  std::vector<double> dy(static_cast<std::size_t>(plant->outputs()), 0.0);
  EXPECT_THAT(error_of([&] { plant->step(du, dy); }), HasSubstr("before reset"));
}

TEST_P(StepErrors, BadSampleTimesAreRefused) {
  auto plant = make_plant(GetParam());
  for (double t : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::infinity()}) {
    EXPECT_THAT(error_of([&] { plant->reset(t); }), HasSubstr("sample_time_min")) << t;
  }
}

TEST_P(StepErrors, WrongSizesAreRefusedByName) {
  auto plant = make_plant(GetParam());
  plant->reset(1.0);
  const auto n = static_cast<std::size_t>(plant->inputs());
  const auto p = static_cast<std::size_t>(plant->outputs());
  std::vector<double> du(n, 0.0), dy(p, 0.0), long_du(n + 1, 0.0), short_dy(p - 1, 0.0);
  EXPECT_THAT(
      error_of([&] { plant->step(long_du, dy); }),
      HasSubstr("du has " + std::to_string(n + 1) + " values, expected " + std::to_string(n)));
  EXPECT_THAT(
      error_of([&] { plant->step(du, short_dy); }),
      HasSubstr("dy has " + std::to_string(p - 1) + " values, expected " + std::to_string(p)));
}

TEST_P(StepErrors, NonFiniteInputsAreRefusedByNameAndNothingMoves) {
  auto plant = make_plant(GetParam());
  plant->reset(1.0);
  const auto n = static_cast<std::size_t>(plant->inputs());
  std::vector<double> du(n, 0.0), dy(static_cast<std::size_t>(plant->outputs()), 0.0);
  du[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(error_of([&] { plant->step(du, dy); }), HasSubstr("du[1] = nan"));
  du[1] = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_of([&] { plant->step(du, dy); }), HasSubstr("du[1] = inf"));
  // The refused samples did not count: the next step is still sample 0, at rest.
  du[1] = amplitude_of(GetParam());
  std::fill(dy.begin(), dy.end(), 1.0);
  plant->step(du, dy);
  for (double v : dy) EXPECT_EQ(v, 0.0);
}

INSTANTIATE_TEST_SUITE_P(OneOfEachKind, StepErrors,
                         ::testing::Values("alatiqi4x4", "colaA", "pilot15"),
                         [](const auto& param_info) { return param_info.param; });

}  // namespace
}  // namespace excite::sim
