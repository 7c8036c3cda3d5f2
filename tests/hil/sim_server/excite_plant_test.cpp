// SPDX-License-Identifier: MIT
// excite-plant as a process: started on an ephemeral port and driven over loopback by hal's
// ModbusFieldBus (exactly the gateway's client code, configured from the same register map)
// and by bare libmodbus for the heartbeat echo and the fault control block.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <modbus.h>

#include <array>
#include <cerrno>
#include <csignal>
#include <thread>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "hal/modbus/modbus_field_bus.hpp"
#include "plant_runner.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/default_map.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {
namespace {

using hal::StatusCode;
using test::PlantRunner;
using test::TempDir;
using ::testing::HasSubstr;

// alatiqi4x4 with float32 setpoints and values in every word order, in both tables.
constexpr const char* kConfig = R"(
[plant]
library = "alatiqi4x4"
sample_time_min = 1.0
input_baseline = [10.0, 20.0, 30.0, 40.0]
output_baseline = [0.5, 0.6, 0.7, 0.8]

[registers]
heartbeat_address = 108
heartbeat_echo_address = 300
heartbeat_echo_function_code = 4
control_address = 400

[[registers.setpoints]]
address = 100
word_order = "CDAB"
[[registers.setpoints]]
address = 102
word_order = "ABCD"
[[registers.setpoints]]
address = 104
word_order = "BADC"
[[registers.setpoints]]
address = 106
word_order = "DCBA"

[[registers.values]]
address = 200
function_code = 4
word_order = "CDAB"
[[registers.values]]
address = 202
function_code = 4
word_order = "DCBA"
[[registers.values]]
address = 204
function_code = 3
word_order = "ABCD"
[[registers.values]]
address = 206
function_code = 3
word_order = "BADC"
)";

constexpr std::array<double, 4> kInputBaseline{10.0, 20.0, 30.0, 40.0};
constexpr std::array<double, 4> kOutputBaseline{0.5, 0.6, 0.7, 0.8};

// Control block registers (sim/server/README.md).
enum Control : int { kStallMs = 400, kStallRequests, kDropRequests, kExceptionRequests, kFreeze };

// One started plant, a gateway-side field bus and a bare libmodbus client on it.
class ExcitePlant : public ::testing::Test {
 protected:
  void start(std::vector<std::string> extra_args) {
    config_path_ = dir_.write("plant.toml", kConfig);
    std::vector<std::string> args{"--config", config_path_.string(), "--port", "0"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    plant_.emplace(args, dir_.path() / "stderr.txt");
    const auto port = plant_->wait_listening();
    ASSERT_TRUE(port) << plant_->first_line() << plant_->stderr_text();
    port_ = *port;

    hal::modbus::ModbusConfig bus_config;
    bus_config.device.port = port_;
    bus_config.device.response_timeout_ms = 300;                  // generous: the machine is shared
    bus_config.map = parse_server_config(kConfig).registers.map;  // the gateway's map
    const auto v = bus_.configure(bus_config);
    ASSERT_TRUE(v.ok()) << v.message();

    ctl_ = modbus_new_tcp("127.0.0.1", port_);
    ASSERT_NE(ctl_, nullptr);
    ASSERT_EQ(modbus_connect(ctl_), 0) << modbus_strerror(errno);
  }

  void TearDown() override {
    if (ctl_ != nullptr) {
      modbus_close(ctl_);
      modbus_free(ctl_);
    }
  }

  std::uint16_t echo() {
    std::uint16_t value = 0;
    EXPECT_EQ(modbus_read_input_registers(ctl_, 300, 1, &value), 1) << modbus_strerror(errno);
    return value;
  }

  void set_control(int address, std::uint16_t value) {
    ASSERT_EQ(modbus_write_register(ctl_, address, value), 1) << modbus_strerror(errno);
  }

  StatusCode exchange(std::uint16_t heartbeat) {
    const std::array<double, 4> u = kInputBaseline;
    std::array<double, 4> y{};
    return bus_.exchange(u, heartbeat, y);
  }

  TempDir dir_;
  std::filesystem::path config_path_;
  std::optional<PlantRunner> plant_;
  std::uint16_t port_ = 0;
  hal::modbus::ModbusFieldBus bus_;
  modbus_t* ctl_ = nullptr;
};

TEST_F(ExcitePlant, LockstepResponseEqualsDiscretePlantSteppedInProcess) {
  const auto log_path = dir_.path() / "run.csv";
  start({"--lockstep", "--log", log_path.string()});
  DiscretePlant reference(library_plant("alatiqi4x4"), 1.0);
  constexpr int kSamples = 60;
  std::vector<std::array<double, 4>> applied;
  std::vector<std::array<double, 4>> deviations;
  double largest_move = 0.0;
  for (int k = 0; k < kSamples; ++k) {
    // GIVEN steps of different lengths on each input (values not representable in float32)
    std::array<double, 4> u{};
    for (std::size_t i = 0; i < 4; ++i) {
      const bool high = ((k / static_cast<int>(3 + 2 * i)) % 2) == 1;
      u[i] = kInputBaseline[i] + (high ? 0.1 : -0.07) * static_cast<double>(i + 1);
    }
    // WHEN the gateway's field bus writes them with heartbeat k + 1 and reads the values
    std::array<double, 4> y{};
    ASSERT_EQ(bus_.exchange(u, static_cast<std::uint16_t>(k + 1), y), StatusCode::ok)
        << bus_.detail();
    // THEN they equal the in-process plant fed the float32-rounded setpoints, rounded to
    // float32 on the way back: bit for bit.
    std::array<double, 4> du{};
    std::array<double, 4> u_sent{};
    for (std::size_t i = 0; i < 4; ++i) {
      u_sent[i] = static_cast<double>(static_cast<float>(u[i]));
      du[i] = u_sent[i] - kInputBaseline[i];
    }
    std::array<double, 4> dy{};
    reference.step(du.data(), dy.data());
    for (std::size_t j = 0; j < 4; ++j) {
      const double expected = static_cast<double>(static_cast<float>(kOutputBaseline[j] + dy[j]));
      EXPECT_EQ(y[j], expected) << "k = " << k << ", output " << j;
      largest_move = std::max(largest_move, std::abs(dy[j]));
    }
    applied.push_back(u_sent);
    deviations.push_back(dy);
  }
  EXPECT_GT(largest_move, 0.1);  // the comparison saw the plant respond, not just baselines

  // The run log holds one row per heartbeat with what the plant applied and produced.
  ASSERT_EQ(plant_->stop(SIGTERM), 0) << plant_->stderr_text();
  const runlog::ReadResult log = runlog::read_run_log(log_path.string());
  ASSERT_TRUE(log.ok()) << log.error->to_string();
  ASSERT_EQ(log.log.rows(), static_cast<std::size_t>(kSamples));
  EXPECT_EQ(log.log.input_names, (std::vector<std::string>{"u1", "u2", "u3", "u4"}));
  for (std::size_t k = 0; k < kSamples; ++k) {
    EXPECT_EQ(log.log.k[k], k);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(log.log.u[i][k], applied[k][i]);
    for (std::size_t j = 0; j < 4; ++j) EXPECT_EQ(log.log.dy[j][k], deviations[k][j]);
  }
}

// The nonlinear column live behind the server: stepping it through Modbus in lock-step gives
// the batch simulation of the same inputs (Plant::simulate), and the gateway's field bus
// reads exactly the plant's outputs around its own operating point.
TEST(ExcitePlantLive, ColumnThroughTheServerEqualsItsBatchSimulation) {
  TempDir dir;
  const auto log_path = dir.path() / "run.csv";
  PlantRunner plant({"--plant", "colaA", "--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep",
                     "--log", log_path.string()},
                    dir.path() / "stderr.txt");
  const auto port = plant.wait_listening();
  ASSERT_TRUE(port) << plant.stderr_text();
  hal::modbus::ModbusConfig bus_config;
  bus_config.device.port = *port;
  bus_config.device.response_timeout_ms = 2000;
  bus_config.map = default_registers(2, 2).map;
  hal::modbus::ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(bus_config).ok());

  const auto reference = make_plant("colaA");
  const Eigen::VectorXd u0 = reference->input_baseline();
  const Eigen::VectorXd y0 = reference->output_baseline();
  constexpr int kSamples = 40;
  std::vector<std::array<double, 2>> read(kSamples);
  std::vector<std::array<double, 2>> sent(kSamples);
  for (std::size_t k = 0; k < kSamples; ++k) {
    sent[k] = {u0(0) + ((k / 7) % 2 == 0 ? 0.01 : -0.01),
               u0(1) + ((k / 5) % 2 == 0 ? -0.01 : 0.01)};
    ASSERT_EQ(bus.exchange(sent[k], static_cast<std::uint16_t>(k + 1), read[k]), StatusCode::ok)
        << bus.detail();
  }
  ASSERT_EQ(plant.stop(SIGTERM), 0) << plant.stderr_text();
  const runlog::ReadResult log = runlog::read_run_log(log_path.string());
  ASSERT_TRUE(log.ok()) << log.error->to_string();
  ASSERT_EQ(log.log.rows(), static_cast<std::size_t>(kSamples));
  EXPECT_EQ(log.log.input_units, (std::vector<std::string>{"kmol/min", "kmol/min"}));
  Eigen::MatrixXd du(kSamples, 2);
  for (int k = 0; k < kSamples; ++k) {
    for (Eigen::Index i = 0; i < 2; ++i) {
      const auto ki = static_cast<std::size_t>(k);
      // the setpoint arrived as float32; du is what the plant applied around u0
      EXPECT_EQ(log.log.u[static_cast<std::size_t>(i)][ki],
                static_cast<double>(static_cast<float>(sent[ki][static_cast<std::size_t>(i)])));
      du(k, i) = log.log.du[static_cast<std::size_t>(i)][ki];
    }
  }
  const Eigen::MatrixXd batch = reference->simulate(du, 1.0);
  double largest = 0.0;
  for (int k = 0; k < kSamples; ++k) {
    for (Eigen::Index j = 0; j < 2; ++j) {
      const double dy = log.log.dy[static_cast<std::size_t>(j)][static_cast<std::size_t>(k)];
      EXPECT_NEAR(dy, batch(k, j), 1e-12) << "k = " << k << ", output " << j;
      EXPECT_EQ(read[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)],
                static_cast<double>(static_cast<float>(y0(j) + dy)));
      largest = std::max(largest, std::abs(batch(k, j)));
    }
  }
  EXPECT_GT(largest, 1e-5);  // the column responded
}

TEST_F(ExcitePlant, RewritingTheSameHeartbeatTakesNoLockstepSample) {
  const auto log_path = dir_.path() / "run.csv";
  start({"--lockstep", "--log", log_path.string()});
  for (const std::uint16_t hb : std::array<std::uint16_t, 6>{7, 7, 7, 8, 8, 9})
    ASSERT_EQ(exchange(hb), StatusCode::ok);
  ASSERT_EQ(plant_->stop(SIGTERM), 0);
  const runlog::ReadResult log = runlog::read_run_log(log_path.string());
  ASSERT_TRUE(log.ok()) << log.error->to_string();
  EXPECT_EQ(log.log.rows(), 3U);  // heartbeats 7, 8, 9
}

TEST_F(ExcitePlant, HeartbeatIsEchoedInLockstepAndFreeRunning) {
  start({"--lockstep"});
  ASSERT_EQ(exchange(41), StatusCode::ok);
  EXPECT_EQ(echo(), 41);
  ASSERT_EQ(exchange(42), StatusCode::ok);
  EXPECT_EQ(echo(), 42);
}

TEST_F(ExcitePlant, FreeRunningEchoFollowsEveryHeartbeatWrite) {
  start({"--sample-time-s", "0.01"});
  for (const std::uint16_t hb : std::array<std::uint16_t, 4>{1, 2, 65535, 0}) {
    ASSERT_EQ(exchange(hb), StatusCode::ok) << bus_.detail();
    EXPECT_EQ(echo(), hb);
  }
}

TEST_F(ExcitePlant, FrozenEchoStaysWhileTheHeartbeatMoves) {
  start({"--lockstep"});
  ASSERT_EQ(exchange(9), StatusCode::ok);
  set_control(kFreeze, 1);
  ASSERT_EQ(exchange(10), StatusCode::ok);
  ASSERT_EQ(exchange(11), StatusCode::ok);
  EXPECT_EQ(echo(), 9);  // stale: the gateway's watchdog should notice
  set_control(kFreeze, 0);
  ASSERT_EQ(exchange(12), StatusCode::ok);
  EXPECT_EQ(echo(), 12);
}

TEST_F(ExcitePlant, StalledReplyTimesTheGatewayOutThenServesAgain) {
  start({"--lockstep"});
  ASSERT_EQ(exchange(1), StatusCode::ok);
  set_control(kStallMs, 700);
  set_control(kStallRequests, 1);
  EXPECT_EQ(exchange(2), StatusCode::timeout);  // 300 ms response timeout < 700 ms stall
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the stall has passed
  EXPECT_EQ(exchange(3), StatusCode::ok) << bus_.detail();
  EXPECT_GE(bus_.reconnects(), 1U);
  std::uint16_t remaining = 99;
  ASSERT_EQ(modbus_read_registers(ctl_, kStallRequests, 1, &remaining), 1);
  EXPECT_EQ(remaining, 0);
}

TEST_F(ExcitePlant, DroppedConnectionIsLostThenTheGatewayReconnects) {
  start({"--lockstep"});
  ASSERT_EQ(exchange(1), StatusCode::ok);
  set_control(kDropRequests, 1);
  EXPECT_EQ(exchange(2), StatusCode::link_lost);
  EXPECT_EQ(exchange(3), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(bus_.reconnects(), 1U);
  EXPECT_EQ(echo(), 3);
}

TEST_F(ExcitePlant, ExceptionReplyIsAPeerErrorAndTheLinkIsKept) {
  start({"--lockstep"});
  ASSERT_EQ(exchange(1), StatusCode::ok);
  set_control(kExceptionRequests, 2);
  EXPECT_EQ(exchange(2), StatusCode::peer_error);
  EXPECT_EQ(exchange(3), StatusCode::peer_error);
  EXPECT_EQ(exchange(4), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(bus_.reconnects(), 0U);
}

TEST_F(ExcitePlant, CommandLineFaultsApplyAfterTheGivenRequests) {
  start({"--lockstep", "--exception-requests", "1", "--faults-after", "2"});
  std::uint16_t value = 0;
  EXPECT_EQ(modbus_read_input_registers(ctl_, 300, 1, &value), 1);
  EXPECT_EQ(modbus_read_input_registers(ctl_, 300, 1, &value), 1);
  EXPECT_EQ(modbus_read_input_registers(ctl_, 300, 1, &value), -1);
  EXPECT_EQ(errno, EMBXSFAIL);
  EXPECT_EQ(modbus_read_input_registers(ctl_, 300, 1, &value), 1);
}

TEST_F(ExcitePlant, UnconfiguredAddressIsAnIllegalDataAddress) {
  start({"--lockstep"});
  std::uint16_t value = 0;
  EXPECT_EQ(modbus_read_input_registers(ctl_, 5000, 1, &value), -1);
  EXPECT_EQ(errno, EMBXILADD);
}

TEST_F(ExcitePlant, FreeRunningPlantAdvancesWithWallClockAndStopsCleanlyOnSigterm) {
  const auto log_path = dir_.path() / "run.csv";
  start({"--sample-time-s", "0.002", "--log", log_path.string()});
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_EQ(plant_->stop(SIGTERM), 0) << plant_->stderr_text();
  EXPECT_THAT(plant_->stderr_text(), HasSubstr("stopped after"));
  const runlog::ReadResult log = runlog::read_run_log(log_path.string());
  ASSERT_TRUE(log.ok()) << log.error->to_string();
  EXPECT_GE(log.log.rows(), 20U);  // ~100 expected; loose: the machine is shared
  EXPECT_EQ(log.log.t_min.back(), static_cast<double>(log.log.rows() - 1));
}

TEST_F(ExcitePlant, SigintAlsoStopsCleanly) {
  start({"--lockstep"});
  EXPECT_EQ(plant_->stop(SIGINT), 0);
}

TEST_F(ExcitePlant, PortInUseExitsWithOneAndLeavesNoLog) {
  start({"--lockstep"});
  const auto log_path = dir_.path() / "second.csv";
  PlantRunner second({"--config", config_path_.string(), "--port", std::to_string(port_), "--log",
                      log_path.string()},
                     dir_.path() / "second-stderr.txt");
  EXPECT_FALSE(second.wait_listening());
  EXPECT_EQ(second.wait_exit(), 1);
  EXPECT_THAT(second.stderr_text(),
              HasSubstr("cannot listen on 127.0.0.1:" + std::to_string(port_)));
  EXPECT_FALSE(std::filesystem::exists(log_path));
  EXPECT_EQ(exchange(1), StatusCode::ok);  // the first plant is unaffected
}

// ---- Bad input: a clear error, exit code 2, nothing served. ----

struct Refused {
  int exit_code;
  std::string first_line;
  std::string stderr_text;
};

Refused run_refused(const std::vector<std::string>& args) {
  TempDir dir;
  std::vector<std::string> full = args;
  for (std::string& a : full) {
    if (a.rfind("@", 0) == 0) a = dir.write("config.toml", a.substr(1)).string();
  }
  PlantRunner plant(full, dir.path() / "stderr.txt");
  const auto port = plant.wait_listening();
  EXPECT_FALSE(port);
  const auto code = plant.wait_exit();
  return {code.value_or(-1), plant.first_line(), plant.stderr_text()};
}

TEST(ExcitePlantBadInput, SetpointCountDifferentFromThePlantInputsIsRefused) {
  std::string text = kConfig;
  const auto at = text.find("[[registers.setpoints]]\naddress = 106");
  text.erase(at, text.find("[[registers.values]]") - at);
  const Refused r = run_refused({"--config", "@" + text, "--port", "0"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.first_line, "");
  EXPECT_THAT(r.stderr_text, HasSubstr("registers.setpoints = 3 entries, expected 4"));
}

TEST(ExcitePlantBadInput, UnknownPlantIsRefused) {
  const Refused r = run_refused({"--config", "@" + std::string(kConfig), "--plant", "nosuch"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.stderr_text, HasSubstr("plant.library = \"nosuch\", expected one of alatiqi4x4"));
}

TEST(ExcitePlantBadInput, UnknownWordOrderIsRefused) {
  std::string text = kConfig;
  text.replace(text.find("\"BADC\""), 6, "\"BACD\"");
  const Refused r = run_refused({"--config", "@" + text});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.stderr_text, HasSubstr("registers.setpoints[2].word_order = \"BACD\""));
}

TEST(ExcitePlantBadInput, UnknownOptionIsRefused) {
  const Refused r = run_refused({"--config", "@" + std::string(kConfig), "--lock-step"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.stderr_text, HasSubstr("--lock-step"));
}

}  // namespace
}  // namespace excite::sim::server
