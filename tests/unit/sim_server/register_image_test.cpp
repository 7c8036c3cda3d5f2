// SPDX-License-Identifier: MIT
// The register image ↔ plant mapping: setpoints written in each word order reach the plant,
// outputs appear in the registers in the configured word order, scaled types follow hal.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/modbus/word_order.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

using hal::modbus::WordOrder;

// Four float32 setpoints (one per word order) and four values (one per word order, FC03
// and FC04 alternating), plus an int16 setpoint and a uint16 value: a 5-input, 5-output map.
ServerLayout five_by_five() {
  const std::string text = R"(
[registers]
heartbeat_address = 120
heartbeat_echo_address = 121
[[registers.setpoints]]
address = 100
word_order = "ABCD"
[[registers.setpoints]]
address = 102
word_order = "CDAB"
[[registers.setpoints]]
address = 104
word_order = "BADC"
[[registers.setpoints]]
address = 106
word_order = "dcba"
[[registers.setpoints]]
address = 108
type = "int16"
eng_min = -50.0
eng_max = 50.0
[[registers.values]]
address = 200
function_code = 3
word_order = "ABCD"
[[registers.values]]
address = 200
function_code = 4
word_order = "CDAB"
[[registers.values]]
address = 202
function_code = 3
word_order = "BADC"
[[registers.values]]
address = 202
function_code = 4
word_order = "DCBA"
[[registers.values]]
address = 204
function_code = 4
type = "uint16"
eng_min = 0.0
eng_max = 1.0
raw_min = 0
raw_max = 27648
)";
  return compile_layout(parse_server_config(text), 5, 5, true);
}

const std::vector<double> kInputBaseline{1.0, 2.0, 3.0, 4.0, 5.0};
const std::vector<double> kOutputBaseline{0.5, 0.25, 0.125, 0.0625, 0.5};

// Registers a gateway would write: 123456.0f (0x47F12000) in each word order.
constexpr std::array<std::array<std::uint16_t, 2>, 4> kOracle{
    {{0x47F1, 0x2000}, {0x2000, 0x47F1}, {0xF147, 0x0020}, {0x0020, 0xF147}}};

TEST(RegisterImage, SetpointsStartAtTheInputBaselineExactly) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  std::vector<double> u(5);
  image.read_setpoints(u.data());
  EXPECT_EQ(u, kInputBaseline);  // not the float32-rounded register contents
  // …and the registers already hold the operating point, for a client that reads them.
  const std::uint16_t r[2] = {image.holding(100), image.holding(101)};
  EXPECT_EQ(hal::modbus::decode_float32(r, WordOrder::abcd), 1.0F);
}

TEST(RegisterImage, FloatSetpointWrittenInEachWordOrderReachesThePlant) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  for (std::uint32_t i = 0; i < 4; ++i) {
    image.set_holding(100 + 2 * i, kOracle[i][0]);
    image.set_holding(101 + 2 * i, kOracle[i][1]);
  }
  image.note_write(100, 8);
  std::vector<double> u(5);
  image.read_setpoints(u.data());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(u[static_cast<std::size_t>(i)], 123456.0) << "input " << i;
  EXPECT_EQ(u[4], 5.0);  // not written yet: still its baseline
}

TEST(RegisterImage, ScaledInt16SetpointIsDecodedAsHalEncodesIt) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  // −25 in −50..50 over −32768..32767: raw = −32768 + 25·65535/100 = −16384.25 → −16384.
  image.set_holding(108, static_cast<std::uint16_t>(-16384 & 0xFFFF));
  image.note_write(108, 1);
  std::vector<double> u(5);
  image.read_setpoints(u.data());
  EXPECT_NEAR(u[4], -25.0, 100.0 / 65535.0);
}

TEST(RegisterImage, NonFiniteFloatSetpointKeepsTheLastGoodValue) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  std::uint16_t r[2];
  hal::modbus::encode_float32(7.5F, WordOrder::abcd, r);
  image.set_holding(100, r[0]);
  image.set_holding(101, r[1]);
  image.note_write(100, 2);
  std::vector<double> u(5);
  image.read_setpoints(u.data());
  EXPECT_EQ(u[0], 7.5);
  image.set_holding(100, 0x7FC0);  // quiet NaN
  image.set_holding(101, 0x0000);
  image.read_setpoints(u.data());
  EXPECT_EQ(u[0], 7.5);
  EXPECT_EQ(image.rejected_setpoints(), 1U);
}

TEST(RegisterImage, OutputsAppearInTheConfiguredWordOrderAndTable) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  const std::vector<double> y{123456.0, 123456.0, 123456.0, 123456.0, 0.5};
  image.write_values(y.data());
  const auto holding = [&](std::uint32_t a) { return image.holding(a); };
  const auto input = [&](std::uint32_t a) { return image.input(a); };
  EXPECT_EQ(holding(200), kOracle[0][0]);
  EXPECT_EQ(holding(201), kOracle[0][1]);
  EXPECT_EQ(input(200), kOracle[1][0]);
  EXPECT_EQ(input(201), kOracle[1][1]);
  EXPECT_EQ(holding(202), kOracle[2][0]);
  EXPECT_EQ(holding(203), kOracle[2][1]);
  EXPECT_EQ(input(202), kOracle[3][0]);
  EXPECT_EQ(input(203), kOracle[3][1]);
  EXPECT_EQ(input(204), 13824);  // 0.5 of 0..27648
}

TEST(RegisterImage, ScaledOutputBeyondItsRangeSaturatesAndIsCounted) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  const std::vector<double> y{0, 0, 0, 0, 1.5};
  image.write_values(y.data());
  EXPECT_EQ(image.input(204), 27648);
  EXPECT_EQ(image.clamped_values(), 1U);
}

TEST(RegisterImage, HeartbeatAndEchoLiveAtTheirAddresses) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  image.set_holding(120, 4711);
  EXPECT_EQ(image.heartbeat(), 4711);
  image.set_heartbeat_echo(4711);
  EXPECT_EQ(image.holding(121), 4711);
}

TEST(PlantProcess, DeviationsAroundTheOperatingPointFollowDiscretePlant) {
  const TransferMatrix g = library_plant("woodberry2x2");
  PlantSettings settings;
  settings.input_baseline = {1.95, 1.71};
  settings.output_baseline = {96.0, 0.5};
  PlantProcess process(make_plant("woodberry2x2"), settings);
  DiscretePlant reference(g, 1.0);
  for (int k = 0; k < 30; ++k) {
    const double u[2] = {1.95 + 0.1 * (k % 3), 1.71 - 0.05 * (k % 5)};
    const double du[2] = {u[0] - 1.95, u[1] - 1.71};
    double y[2];
    double dy[2];
    process.sample(u, y);
    reference.step(du, dy);
    EXPECT_EQ(y[0], 96.0 + dy[0]) << "k = " << k;
    EXPECT_EQ(y[1], 0.5 + dy[1]) << "k = " << k;
  }
  EXPECT_EQ(process.samples(), 30U);
}

TEST(PlantProcess, ColumnAroundItsOwnOperatingPointEqualsItsBatchSimulation) {
  // GIVEN colaA live, with no baselines configured: the plant's own operating point
  PlantSettings settings;
  PlantProcess process(make_plant("colaA"), settings);
  const auto reference = make_plant("colaA");
  const Eigen::VectorXd u0 = reference->input_baseline();
  const Eigen::VectorXd y0 = reference->output_baseline();
  ASSERT_EQ(process.input_baseline(), std::vector<double>(u0.data(), u0.data() + u0.size()));
  ASSERT_EQ(process.output_baseline(), std::vector<double>(y0.data(), y0.data() + y0.size()));
  EXPECT_GT(u0.norm(), 1.0);  // absolute flows, not deviations
  // WHEN it is fed steps of 0.01 kmol/min for 40 samples
  constexpr int kSamples = 40;
  Eigen::MatrixXd du(kSamples, 2);
  Eigen::MatrixXd y(kSamples, 2);
  for (int k = 0; k < kSamples; ++k) {
    du(k, 0) = (k / 7) % 2 == 0 ? 0.01 : -0.01;
    du(k, 1) = (k / 5) % 2 == 0 ? -0.01 : 0.01;
    const double u[2] = {u0(0) + du(k, 0), u0(1) + du(k, 1)};
    double yk[2];
    process.sample(u, yk);
    y(k, 0) = yk[0] - y0(0);
    y(k, 1) = yk[1] - y0(1);
    du(k, 0) = process.last_du()[0];  // exactly what the plant was given
    du(k, 1) = process.last_du()[1];
  }
  // THEN the deviations equal the batch simulation of the same inputs
  const Eigen::MatrixXd batch = reference->simulate(du, 1.0);
  EXPECT_LT((y - batch).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(batch.cwiseAbs().maxCoeff(), 1e-5);  // the column responded
}

TEST(PlantProcess, NoiseIsTheSeededMeasurementNoise) {
  const TransferMatrix g = library_plant("woodberry2x2");
  PlantSettings settings;
  settings.noise_variance = {0.03};
  settings.noise_seed = 42;
  PlantProcess process(make_plant("woodberry2x2"), settings);
  EXPECT_EQ(process.outputs(), g.outputs());
  MeasurementNoise noise(2, 0.03, 42);
  const double u[2] = {0.0, 0.0};
  for (int k = 0; k < 10; ++k) {
    double y[2];
    process.sample(u, y);
    double expected[2] = {0.0, 0.0};
    noise.add(expected);
    EXPECT_EQ(y[0], expected[0]);
    EXPECT_EQ(y[1], expected[1]);
  }
}

// The plant's own limits, checked on a request's bytes before they are written.
TEST(RegisterImage, CheckWriteFindsASetpointOutsideItsLimits) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  const std::vector<double> lo(5, -10.0);
  const std::vector<double> hi(5, 10.0);
  const auto bytes = [](float x) {
    std::uint16_t r[2];
    hal::modbus::encode_float32(x, WordOrder::abcd, r);
    return std::array<std::uint8_t, 4>{
        static_cast<std::uint8_t>(r[0] >> 8), static_cast<std::uint8_t>(r[0] & 0xFF),
        static_cast<std::uint8_t>(r[1] >> 8), static_cast<std::uint8_t>(r[1] & 0xFF)};
  };
  const auto big = bytes(1e30F);
  const auto out = image.check_write(100, 2, big.data(), lo, hi);
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(out->input, 0U);
  EXPECT_FLOAT_EQ(static_cast<float>(out->value), 1e30F);
  EXPECT_FALSE(image.check_write(110, 2, big.data(), lo, hi).has_value()) << "no setpoint there";
  const auto fine = bytes(9.5F);
  EXPECT_FALSE(image.check_write(100, 2, fine.data(), lo, hi).has_value());
  // int16 scaled setpoint at 108: raw 32767 is eng 50, beyond 10.
  const std::uint8_t raw_max[2] = {0x7F, 0xFF};
  const auto scaled = image.check_write(108, 1, raw_max, lo, hi);
  ASSERT_TRUE(scaled.has_value());
  EXPECT_EQ(scaled->input, 4U);
}

TEST(RegisterImage, RestoreSetpointBaselineRewritesTheRegisters) {
  RegisterImage image(five_by_five(), kInputBaseline, kOutputBaseline);
  const std::vector<std::uint16_t> baseline = image.setpoint_registers();
  image.set_holding(100, 0x4120);  // 10.0f, ABCD
  image.set_holding(101, 0x0000);
  image.note_write(100, 2);
  std::vector<double> u(5);
  image.read_setpoints(u.data());
  EXPECT_EQ(u[0], 10.0);
  const std::vector<std::uint16_t> written = image.setpoint_registers();
  image.restore_setpoint_baseline();
  EXPECT_EQ(image.setpoint_registers(), baseline);
  image.read_setpoints(u.data());
  EXPECT_EQ(u[0], kInputBaseline[0]);
  image.set_setpoint_registers(written);
  image.read_setpoints(u.data());
  EXPECT_EQ(u[0], 10.0);
}

}  // namespace
}  // namespace excite::sim::server
