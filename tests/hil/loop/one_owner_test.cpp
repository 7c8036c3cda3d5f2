// SPDX-License-Identifier: MIT
// Issue 39 §1, with the real gateway and the real plant server over a real socket: one owner
// of the plant's setpoints.
//  - a second excite-gateway with the same configuration, started while the first streams,
//    refuses to arm (exit 5, "another master is writing", no run log) and writes nothing: the
//    first completes and the plant's own log ends at its baseline (before: the second armed
//    on the first one's excitation as its "baseline", both exited 0 and the plant stayed
//    excited);
//  - another master writing the heartbeat register, or a setpoint, while the gateway runs is
//    a fault: the gateway stops the excitation, confirms its baseline, exits 11 and says
//    another writer was seen (before: its next write covered the foreign one, nothing was
//    seen, exit 0 "completed").
// The foreign master is a libmodbus client of excite-plant, as an operator station would be.
#include <modbus.h>

#include <cmath>
#include <cstring>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

constexpr int kSetpointU1 = 100;  // loop-config's map: u1 float32 ABCD at holding 100
constexpr int kHeartbeat = 104;   // the heartbeat register ([map] heartbeat_address)

/// A second Modbus master on the plant server: writes what a test tells it to.
class ForeignMaster {
 public:
  explicit ForeignMaster(std::uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    connected_ = ctx_ != nullptr && modbus_connect(ctx_) == 0;
    if (ctx_ != nullptr) modbus_set_slave(ctx_, 1);
  }
  ~ForeignMaster() {
    if (ctx_ != nullptr) {
      modbus_close(ctx_);
      modbus_free(ctx_);
    }
  }
  ForeignMaster(const ForeignMaster&) = delete;
  ForeignMaster& operator=(const ForeignMaster&) = delete;

  [[nodiscard]] bool connected() const { return connected_; }
  bool write_heartbeat(std::uint16_t value) {
    return modbus_write_register(ctx_, kHeartbeat, value) == 1;
  }
  bool write_u1(float value) {
    // float32 ABCD: the high word first, each big-endian (the map loop-config writes).
    std::uint32_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    std::uint16_t regs[2] = {static_cast<std::uint16_t>(bits >> 16U),
                             static_cast<std::uint16_t>(bits & 0xFFFFU)};
    return modbus_write_registers(ctx_, kSetpointU1, 2, regs) == 2;
  }

 private:
  modbus_t* ctx_;
  bool connected_ = false;
};

class OneOwner : public LoopTest {
 protected:
  /// The loop in real time at 5 ms ticks (945 rows: about 5 s), the plant in lock-step.
  void start() {
    port_ = start_loop(kPlant, "--input-range 2 --period-s 0.005");
    plan_ = design(kPlant, "prbsUnc");
  }

  /// Waits until the gateway's stderr says it runs (the state change of tick 0).
  static bool wait_running(GatewayProcess& gw) {
    for (int i = 0; i < 1000; ++i) {
      if (gw.err().find("-> running") != std::string::npos) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  void expect_plant_back_at_baseline() {
    const runlog::RunLog plant = stop_plant_and_read_its_log();
    ASSERT_GT(plant.rows(), 10U);
    for (std::size_t i = 0; i < plant.du.size(); ++i) {
      EXPECT_LE(std::abs(plant.du[i].back()), 1e-6) << plant.input_names[i] << " left excited";
    }
  }

  std::uint16_t port_ = 0;
  fs::path plan_;
};

// GIVEN a gateway streaming to the plant WHEN a second one with the same configuration and
// plan starts THEN the second refuses to arm, names the value that moved, writes nothing and
// leaves no log; the first completes and the plant ends at its baseline.
TEST_F(OneOwner, ASecondGatewayRefusesToArmWhileAnotherMasterWrites) {
  start();
  auto first = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_running(*first)) << first->err();
  GatewayProcess second(EXCITE_GATEWAY,
                        {"--config", path("gateway.toml").string(), "--plan", plan_.string(),
                         "--log", path("second.csv").string(), "--start"},
                        path("second").string());
  const auto rc2 = second.wait(30s);
  ASSERT_TRUE(rc2.has_value()) << second.err();
  const std::string err2 = second.err();
  EXPECT_EQ(*rc2, 5) << err2;
  EXPECT_NE(err2.find("refused to arm: another master is writing: "), std::string::npos) << err2;
  EXPECT_NE(err2.find(" in two reads "), std::string::npos) << err2;
  EXPECT_NE(err2.find("expected unchanged"), std::string::npos) << err2;
  EXPECT_FALSE(fs::exists(path("second.csv"))) << "a refused start leaves no run log";

  const auto rc1 = first->wait(60s);
  ASSERT_TRUE(rc1.has_value()) << first->err();
  EXPECT_EQ(*rc1, 0) << first->err();
  EXPECT_NE(first->err().find("safe after"), std::string::npos) << first->err();
  expect_plant_back_at_baseline();
}

// GIVEN a gateway streaming WHEN another master writes the heartbeat register THEN the gateway
// stops the excitation (a fault), confirms its baseline, exits 11 and names the echo it never
// sent; its log ends safe and the plant at its baseline.
TEST_F(OneOwner, AForeignHeartbeatWhileRunningIsAFaultEndingConfirmedSafe) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_running(*gw)) << gw->err();
  std::this_thread::sleep_for(300ms);  // well into the table (60 of 945 rows)
  {
    ForeignMaster other(port_);
    ASSERT_TRUE(other.connected());
    for (std::uint16_t k = 0; k < 5; ++k) {
      ASSERT_TRUE(other.write_heartbeat(static_cast<std::uint16_t>(40000 + k)));
      std::this_thread::sleep_for(3ms);
    }
  }
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 11) << err;
  EXPECT_NE(err.find("fault: another writer was seen: heartbeat echo hb_echo = 4000"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("excite-gateway: safe after"), std::string::npos) << err;
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(log.rows(), 2U);
  EXPECT_EQ(log.state.back(), runlog::RunState::safe);
  EXPECT_LT(log.rows(), 945U) << "the excitation went on to the table's end";
  expect_plant_back_at_baseline();
}

// The same with another master writing setpoint u1 (a value the gateway never wrote).
TEST_F(OneOwner, AForeignSetpointWhileRunningIsAFaultEndingConfirmedSafe) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_running(*gw)) << gw->err();
  std::this_thread::sleep_for(300ms);
  {
    ForeignMaster other(port_);
    ASSERT_TRUE(other.connected());
    for (int k = 0; k < 5; ++k) {
      ASSERT_TRUE(other.write_u1(1.25F));
      std::this_thread::sleep_for(3ms);
    }
  }
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 11) << err;
  EXPECT_NE(err.find("fault: another writer was seen: setpoint u1 (register 100 float32 ABCD) "
                     "= 1.25 read back from u1_sp"),
            std::string::npos)
      << err;
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(log.rows(), 2U);
  EXPECT_EQ(log.state.back(), runlog::RunState::safe);
  expect_plant_back_at_baseline();
}

}  // namespace
}  // namespace excite::test
