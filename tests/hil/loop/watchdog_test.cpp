// SPDX-License-Identifier: MIT
// The plant's own controller, with the real gateway and the real plant server: the
// heartbeat watchdog returns the plant's inputs to the baseline after the gateway is
// SIGKILLed mid-run (seen on the plant's side: its setpoint registers read with libmodbus,
// its control block, its run log, its stderr), and the plant's input limits refuse a write
// beyond them with exception 3 and count it.
#include <modbus.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// The default register map (sim/server/README.md) for woodberry2x2: setpoints float32 ABCD
// at holding 100..103, the control block at holding 400..407.
constexpr int kSetpoints = 100;
constexpr int kSetpointRegisters = 4;
constexpr int kRefusedWrites = 407;  // control block +7
constexpr double kWatchdogS = 0.5;

// A libmodbus client of the plant server: an observer beside the gateway.
class Observer {
 public:
  explicit Observer(std::uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    if (ctx_ != nullptr && modbus_connect(ctx_) != 0) {
      modbus_free(ctx_);
      ctx_ = nullptr;
    }
  }
  ~Observer() {
    if (ctx_ != nullptr) {
      modbus_close(ctx_);
      modbus_free(ctx_);
    }
  }
  Observer(const Observer&) = delete;
  Observer& operator=(const Observer&) = delete;
  bool ok() const { return ctx_ != nullptr; }
  modbus_t* ctx() { return ctx_; }

  std::vector<std::uint16_t> read(int address, int count) {
    std::vector<std::uint16_t> r(static_cast<std::size_t>(count));
    if (modbus_read_registers(ctx_, address, count, r.data()) != count) return {};
    return r;
  }
  int read_one(int address) {
    const auto r = read(address, 1);
    return r.empty() ? -1 : r[0];
  }
  float read_float(int address) {
    const auto r = read(address, 2);
    if (r.empty()) return NAN;
    const std::uint32_t bits = (std::uint32_t{r[0]} << 16) | r[1];  // ABCD: high word first
    float x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
  }
  // Writes one float32 ABCD setpoint; returns libmodbus's rc (2, or −1 with errno).
  int write_float(int address, float value) {
    // Encoded here, not with libmodbus's float helpers (wrong byte order in 3.1.6).
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    const std::uint16_t r[2] = {static_cast<std::uint16_t>(bits >> 16),
                                static_cast<std::uint16_t>(bits & 0xFFFF)};
    return modbus_write_registers(ctx_, address, 2, r);
  }

 private:
  modbus_t* ctx_;
};

class Watchdog : public LoopTest {
 protected:
  // The loop for woodberry2x2, a gateway ticking every 5 ms, the plant's watchdog at 0.5 s.
  void start(const std::vector<std::string>& plant_args) {
    port_ = start_loop(kPlant, "--input-range 2 --period-s 0.005", plant_args);
    plan_ = design(kPlant, "prbsUnc");
  }

  // SIGKILLs the gateway mid-run and asserts, on the plant's side, that within the
  // watchdog timeout + 0.5 s (not before the timeout) its setpoint registers hold the
  // baseline again and the trip is counted in its control block.
  void kill_the_gateway_and_expect_the_plant_back_at_baseline() {
    Observer plc(port_);
    ASSERT_TRUE(plc.ok()) << modbus_strerror(errno);
    const std::vector<std::uint16_t> baseline = plc.read(kSetpoints, kSetpointRegisters);
    ASSERT_EQ(baseline.size(), 4U);
    auto gw = start_gateway(plan_, {"--start"});
    // Mid-run: the setpoints have left the baseline, and the gateway has streamed a while.
    const auto until = SteadyClock::now() + 20s;
    while (plc.read(kSetpoints, kSetpointRegisters) == baseline && SteadyClock::now() < until) {
      std::this_thread::sleep_for(10ms);
    }
    std::this_thread::sleep_for(500ms);
    ASSERT_FALSE(gw->wait(0ms).has_value()) << "the run ended too soon: " << gw->err();
    EXPECT_EQ(plc.read_one(kWatchdogTrips), 0) << "a healthy run trips nothing";
    EXPECT_NE(plc.read(kSetpoints, kSetpointRegisters), baseline) << "the plant is excited";

    gw->signal(SIGKILL);
    const auto killed = SteadyClock::now();
    ASSERT_EQ(gw->wait(10s).value_or(-1), 128 + SIGKILL);
    std::vector<std::uint16_t> now;
    int trips = 0;
    while (SteadyClock::now() - killed < std::chrono::duration<double>(kWatchdogS + 0.5)) {
      now = plc.read(kSetpoints, kSetpointRegisters);
      trips = plc.read_one(kWatchdogTrips);
      if (now == baseline && trips == 1) break;
      std::this_thread::sleep_for(10ms);
    }
    const double after_s = std::chrono::duration<double>(SteadyClock::now() - killed).count();
    EXPECT_EQ(now, baseline) << "the plant's inputs are not back at baseline " << after_s
                             << " s after the gateway died";
    EXPECT_EQ(trips, 1) << "the watchdog trip is counted in the control block (+6)";
    EXPECT_GE(after_s, kWatchdogS - 0.05) << "the watchdog tripped before its timeout";
    std::printf("[ measured ] plant back at baseline %.3f s after SIGKILL (watchdog %.1f s)\n",
                after_s, kWatchdogS);
    // Held there: nothing moves the inputs while the heartbeat stands still.
    std::this_thread::sleep_for(300ms);
    EXPECT_EQ(plc.read(kSetpoints, kSetpointRegisters), baseline);
    EXPECT_EQ(plc.read_one(kWatchdogTrips), 1) << "one stale heartbeat, one trip";
  }

  std::uint16_t port_ = 0;
  fs::path plan_;
};

TEST_F(Watchdog, LockstepPlantReturnsToBaselineAfterTheGatewayIsSigkilled) {
  start({"--clock", "lockstep", "--watchdog-s", "0.5"});
  kill_the_gateway_and_expect_the_plant_back_at_baseline();
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  // The gateway streamed a while: at least 500 ms of 5-ms ticks after the first excitation
  // (100 rows at full speed; 95 seen in the sanitizer build, preset asan-hil).
  EXPECT_GE(plant.rows(), 50U);
  const std::string err = plant_->stderr_text();
  EXPECT_NE(err.find("watchdog: heartbeat unchanged for"), std::string::npos) << err;
  EXPECT_NE(err.find(" 1 watchdog trips"), std::string::npos) << err;
}

// A free-running plant keeps sampling: its own run log ends at the baseline.
TEST_F(Watchdog, RealtimePlantLogsItsInputsBackAtBaseline) {
  // woodberry2x2: T = 1 min; speedup 12000 → one sample per 5 ms, the gateway's period.
  start({"--clock", "realtime", "--speedup", "12000", "--watchdog-s", "0.5"});
  kill_the_gateway_and_expect_the_plant_back_at_baseline();
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  ASSERT_GT(plant.rows(), 100U);
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    double excited = 0.0;
    for (double du : plant.du[i]) excited = std::max(excited, std::abs(du));
    EXPECT_GT(excited, 0.01) << plant.input_names[i]
                             << " was never excited";  // amplitudes 0.04, 0.07
    EXPECT_LE(std::abs(plant.du[i].back()), 1e-6 * (1 + std::abs(plant.u[i].back())))
        << plant.input_names[i] << " is not back at its baseline in the plant's own log";
  }
}

// The PLC's rule with a bare Modbus master (libmodbus): the watchdog arms on the first
// heartbeat, a setpoint written while tripped is held back (the registers read the
// baseline), and applies when the heartbeat moves again; the plant then samples it.
TEST_F(Watchdog, SetpointsWrittenWhileTrippedApplyOnlyWhenTheHeartbeatMoves) {
  start({"--clock", "lockstep", "--watchdog-s", "0.3"});
  Observer master(port_);
  ASSERT_TRUE(master.ok()) << modbus_strerror(errno);
  const int heartbeat = kSetpoints + kSetpointRegisters;  // default map: after the setpoints
  const std::vector<std::uint16_t> baseline = master.read(kSetpoints, kSetpointRegisters);
  const float u0 = master.read_float(kSetpoints);
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(master.read_one(kWatchdogTrips), 0) << "not armed before the first heartbeat";

  ASSERT_EQ(master.write_float(kSetpoints, u0 + 1.0F), 2);
  ASSERT_EQ(modbus_write_register(master.ctx(), heartbeat, 1), 1);
  EXPECT_EQ(master.read_float(kSetpoints), u0 + 1.0F);
  std::this_thread::sleep_for(600ms);
  EXPECT_EQ(master.read_one(kWatchdogTrips), 1);
  EXPECT_EQ(master.read(kSetpoints, kSetpointRegisters), baseline) << "tripped: baseline";

  ASSERT_EQ(master.write_float(kSetpoints, u0 + 0.5F), 2);
  EXPECT_EQ(master.read(kSetpoints, kSetpointRegisters), baseline)
      << "a setpoint written while tripped does not apply before the heartbeat moves";
  ASSERT_EQ(modbus_write_register(master.ctx(), heartbeat, 1), 1);
  EXPECT_EQ(master.read(kSetpoints, kSetpointRegisters), baseline) << "rewriting the same "
                                                                      "heartbeat moves nothing";
  ASSERT_EQ(modbus_write_register(master.ctx(), heartbeat, 2), 1);
  EXPECT_EQ(master.read_float(kSetpoints), u0 + 0.5F) << "the heartbeat moved: it applies";
  EXPECT_EQ(master.read_one(kWatchdogTrips), 1);

  // The plant's log: sample 0 at u0 + 1, sample 1 (heartbeat 2) at u0 + 0.5 — the value
  // written while tripped, sampled when the heartbeat moved.
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  ASSERT_EQ(plant.rows(), 2U);
  EXPECT_NEAR(plant.du[0][0], 1.0, 1e-6);
  EXPECT_NEAR(plant.du[0][1], 0.5, 1e-6);
  EXPECT_NE(plant_->stderr_text().find("watchdog: heartbeat moves again"), std::string::npos)
      << plant_->stderr_text();
}

// loop-config writes the gateway's limits into plant.toml: a write beyond them (from a
// client that is not the gateway, or a gateway misconfigured) is refused with exception 3,
// nothing is written, and the refusal is counted. The gateway's own run stays untouched.
TEST_F(Watchdog, WriteBeyondThePlantsLimitsIsRefusedAndCounted) {
  start({"--clock", "lockstep"});
  Observer client(port_);
  ASSERT_TRUE(client.ok()) << modbus_strerror(errno);
  const float u0 = client.read_float(kSetpoints);
  ASSERT_TRUE(std::isfinite(u0));
  EXPECT_EQ(client.write_float(kSetpoints, 1e30F), -1);
  EXPECT_EQ(errno, EMBXILVAL) << modbus_strerror(errno);
  EXPECT_EQ(client.write_float(kSetpoints, u0 + static_cast<float>(kInputRange) + 0.01F), -1);
  EXPECT_EQ(errno, EMBXILVAL) << modbus_strerror(errno);
  EXPECT_EQ(client.write_float(kSetpoints, NAN), -1) << "not a number is outside every limit";
  EXPECT_EQ(client.read_float(kSetpoints), u0) << "a refused write writes nothing";
  EXPECT_EQ(client.read_one(kRefusedWrites), 3);
  EXPECT_EQ(client.write_float(kSetpoints, u0 + 1.5F), 2) << modbus_strerror(errno);
  EXPECT_EQ(client.read_float(kSetpoints), u0 + 1.5F);
  EXPECT_EQ(client.read_one(kRefusedWrites), 3) << "a write inside the limits is not counted";

  // The real gateway's run, inside the same limits, is never refused.
  ASSERT_EQ(client.write_float(kSetpoints, u0), 2);
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(gw->wait(120s).has_value()) << gw->err();
  EXPECT_EQ(client.read_one(kRefusedWrites), 3) << gw->err();
  stop_plant_and_read_its_log();
  const std::string err = plant_->stderr_text();
  EXPECT_NE(err.find("write refused (exception 3, illegal data value)"), std::string::npos) << err;
  EXPECT_NE(err.find(" 3 writes refused for the input limits"), std::string::npos) << err;
}

// excite-plant --input-range R: limits baseline ± R on the command line (over plant.toml's).
TEST_F(Watchdog, InputRangeOnTheCommandLineOverridesTheConfiguredLimits) {
  start({"--clock", "lockstep", "--input-range", "1"});
  Observer client(port_);
  ASSERT_TRUE(client.ok()) << modbus_strerror(errno);
  const float u0 = client.read_float(kSetpoints);
  EXPECT_EQ(client.write_float(kSetpoints, u0 + 1.5F), -1) << "inside ±2, outside ±1";
  EXPECT_EQ(errno, EMBXILVAL);
  EXPECT_EQ(client.write_float(kSetpoints, u0 + 0.5F), 2) << modbus_strerror(errno);
  EXPECT_EQ(client.read_one(kRefusedWrites), 1);
}

// Configured limits that do not fit the plant are refused by name before anything is served.
TEST_F(Watchdog, LimitsThatMissTheBaselineOrThePlantAreRefusedByName) {
  loop_config(kPlant, 1502, "--input-range 2");
  std::ifstream in(path("plant.toml"));
  std::ostringstream text;
  text << in.rdbuf();
  const std::string good = text.str();
  const auto at = good.find("input_min = [");
  ASSERT_NE(at, std::string::npos) << good;
  const auto end = good.find('\n', at);
  const struct {
    std::string line, message;
  } cases[] = {
      {"input_min = [1.0, -2.0]", "plant.input_min/input_max[0] = [1, "},
      {"input_min = [-2.0, -2.0, -2.0]", "plant.input_max = (2 values), expected as many"},
  };
  for (const auto& c : cases) {
    std::ofstream(path("bad.toml")) << good.substr(0, at) + c.line + good.substr(end);
    PlantRunner plant({"--config", path("bad.toml").string(), "--modbus-tcp", "127.0.0.1:0"},
                      path("bad.err"));
    EXPECT_EQ(plant.wait_exit().value_or(-1), 2) << c.line;
    EXPECT_NE(plant.stderr_text().find(c.message), std::string::npos)
        << c.line << ": " << plant.stderr_text();
  }
}

TEST_F(Watchdog, NegativeOrNanWatchdogIsRefusedByName) {
  loop_config(kPlant, 1502, "--input-range 2");
  for (const std::string bad : {"-1", "nan"}) {
    PlantRunner plant({"--config", path("plant.toml").string(), "--modbus-tcp", "127.0.0.1:0",
                       "--watchdog-s", bad},
                      path("bad.err"));
    EXPECT_EQ(plant.wait_exit().value_or(-1), 2) << "--watchdog-s " << bad;
    EXPECT_NE(plant.stderr_text().find("--watchdog-s = " + bad), std::string::npos)
        << plant.stderr_text();
  }
}

}  // namespace
}  // namespace excite::test
