// SPDX-License-Identifier: MIT
// excite-plant --controller (issue 42 §1), the real process on an ephemeral port driven by a
// bare libmodbus client standing in for the gateway: the test offsets it writes move the
// plant through the controller (equal, sample for sample, to the same loop stepped in this
// process), the controller holds its setpoints, the operator's switch puts it in manual,
// the MVs are the controller's (a setpoint write is refused), the watchdog returns every
// offset to zero and keeps the controller in control (asserted on the plant's side: its
// registers, its controller log, its stderr), and a bad controller file is refused by name.
#include <gtest/gtest.h>
#include <modbus.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "plant_runner.hpp"
#include "sim/server/load_closed_loop.hpp"
#include "sim/server/plant_process.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
namespace server = excite::sim::server;

const std::string kPi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";

// The default map under a controller for woodberry2x2 (n = m = 2; sim/server/README.md,
// "Closed loop"): offsets at holding 500 (MVs) and 504 (CV setpoints), the heartbeat at 508;
// the controller's block at input 500; the switch at holding 410.
constexpr int kOffsets = 500;
constexpr int kHeartbeat = 508;
constexpr int kMoves = 500;
constexpr int kApplied = 504;
constexpr int kSetpointsInForce = 508;
constexpr int kStatus = 512;
constexpr int kMode = 514;
constexpr int kSwitch = 410;
constexpr int kSetpointRegisters = 100;  // holding: the applied MVs, absolute
constexpr int kOutputs = 200;            // input: y1, y2
constexpr int kWatchdogTrips = 406;      // control block +6

float to_float(std::uint16_t hi, std::uint16_t lo) {
  const std::uint32_t bits = (std::uint32_t{hi} << 16) | lo;  // ABCD
  float x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

void from_float(float x, std::uint16_t* r) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  r[0] = static_cast<std::uint16_t>(bits >> 16);
  r[1] = static_cast<std::uint16_t>(bits & 0xFFFF);
}

// A bare Modbus master: what the gateway does in closed loop, by hand.
class Master {
 public:
  explicit Master(std::uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    if (ctx_ != nullptr && modbus_connect(ctx_) != 0) {
      modbus_free(ctx_);
      ctx_ = nullptr;
    }
  }
  ~Master() {
    if (ctx_ != nullptr) {
      modbus_close(ctx_);
      modbus_free(ctx_);
    }
  }
  Master(const Master&) = delete;
  Master& operator=(const Master&) = delete;
  bool ok() const { return ctx_ != nullptr; }
  modbus_t* ctx() { return ctx_; }

  // One tick: the four offsets (u1, u2, y1 setpoint, y2 setpoint) and the heartbeat in one
  // FC16 request, as the gateway writes them (address order, the heartbeat last).
  bool tick(const std::array<float, 4>& offsets) {
    std::uint16_t r[9];
    for (std::size_t k = 0; k < 4; ++k) from_float(offsets[k], r + 2 * k);
    r[8] = ++heartbeat_;
    return modbus_write_registers(ctx_, kOffsets, 9, r) == 9;
  }
  bool beat() {  // the heartbeat alone
    return modbus_write_register(ctx_, kHeartbeat, ++heartbeat_) == 1;
  }
  float input_float(int address) {
    std::uint16_t r[2] = {0, 0};
    if (modbus_read_input_registers(ctx_, address, 2, r) != 2) return NAN;
    return to_float(r[0], r[1]);
  }
  float holding_float(int address) {
    std::uint16_t r[2] = {0, 0};
    if (modbus_read_registers(ctx_, address, 2, r) != 2) return NAN;
    return to_float(r[0], r[1]);
  }
  int input_one(int address) {
    std::uint16_t r = 0;
    return modbus_read_input_registers(ctx_, address, 1, &r) == 1 ? r : -1;
  }
  int holding_one(int address) {
    std::uint16_t r = 0;
    return modbus_read_registers(ctx_, address, 1, &r) == 1 ? r : -1;
  }

 private:
  modbus_t* ctx_;
  std::uint16_t heartbeat_ = 0;
};

class ClosedLoopPlant : public ::testing::Test {
 protected:
  std::uint16_t start(std::vector<std::string> extra) {
    std::vector<std::string> args{"--plant",          "woodberry2x2",
                                  "--controller",     kPi,
                                  "--modbus-tcp",     "127.0.0.1:0",
                                  "--controller-log", (dir_.path() / "controller.csv").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    plant_ = std::make_unique<PlantRunner>(args, dir_.path() / "stderr.txt");
    const auto port = plant_->wait_listening();
    EXPECT_TRUE(port.has_value()) << plant_->stderr_text();
    return port.value_or(0);
  }
  std::vector<std::string> controller_log() const {
    std::ifstream in(dir_.path() / "controller.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  TempDir dir_;
  std::unique_ptr<PlantRunner> plant_;
};

// GIVEN the PI on woodberry2x2 in the plant's loop, WHEN the master writes an MV test offset,
// THEN the plant gets the controller's move plus the offset, and every sample equals the
// same loop (sim/server's ClosedLoop and PlantProcess) stepped in this process.
TEST_F(ClosedLoopPlant, AnMvOffsetMovesThePlantThroughTheControllerAsInProcess) {
  Master gw(start({"--clock", "lockstep"}));
  ASSERT_TRUE(gw.ok());
  EXPECT_EQ(gw.input_one(kMode), 1) << "at rest: in control";

  server::PlantSettings settings;
  settings.library = "woodberry2x2";
  server::PlantProcess process(server::load_plant(settings, "."), settings);
  const auto loop = server::load_closed_loop(kPi, process.plant(), 1.0);
  std::vector<double> y_measured(2, 0.0);
  std::vector<double> u(2);
  std::vector<double> y(2);
  const std::vector<double> sp{0.0, 0.0};
  double largest_move = 0.0;
  for (int k = 0; k < 120; ++k) {
    const float offset = k < 60 ? 0.1F : -0.05F;
    ASSERT_TRUE(gw.tick({offset, 0.0F, 0.0F, 0.0F})) << modbus_strerror(errno);
    const std::vector<double> mv{static_cast<double>(offset), 0.0};
    loop->step(y_measured, 1, mv, sp);
    for (std::size_t i = 0; i < 2; ++i) u[i] = loop->applied()[i];
    process.sample(u.data(), y.data());
    y_measured = process.last_dy();
    for (int j = 0; j < 2; ++j) {
      ASSERT_EQ(gw.input_float(kOutputs + 2 * j),
                static_cast<float>(y[static_cast<std::size_t>(j)]))
          << "sample " << k << " output " << j;
    }
    for (int i = 0; i < 2; ++i) {
      const auto at = static_cast<std::size_t>(i);
      ASSERT_EQ(gw.input_float(kMoves + 2 * i), static_cast<float>(loop->moves()[at])) << k;
      ASSERT_EQ(gw.input_float(kApplied + 2 * i), static_cast<float>(loop->applied()[at])) << k;
      ASSERT_EQ(gw.holding_float(kSetpointRegisters + 2 * i), static_cast<float>(u[at]))
          << "the setpoint registers carry the applied MV";
    }
    largest_move = std::max(largest_move, std::abs(loop->moves()[0]));
  }
  EXPECT_EQ(loop->applied()[0], loop->moves()[0] + static_cast<double>(-0.05F))
      << "applied = move + offset";
  EXPECT_GT(largest_move, 0.01) << "the PI works against the offset on xD";
  EXPECT_GT(std::abs(y[0]), 1e-3) << "the offset moved the plant";
  EXPECT_EQ(gw.input_one(kMode), 2) << "a non-zero offset: mode test";
  EXPECT_EQ(gw.input_one(kStatus), 0);
  // The controller log: a header and one row per sample.
  EXPECT_EQ(controller_log().size(), 121U);
  EXPECT_EQ(controller_log().front(),
            "event,k,t_min,mode,o_u1,o_u2,uc_u1,uc_u2,du_u1,du_u2,st_u1,st_u2,ysp_y1,ysp_y2");
}

// A setpoint offset: the controller takes xD there and holds xB, with no offset left.
TEST_F(ClosedLoopPlant, TheControllerHoldsItsSetpoints) {
  Master gw(start({"--clock", "lockstep"}));
  ASSERT_TRUE(gw.ok());
  for (int k = 0; k < 500; ++k) ASSERT_TRUE(gw.tick({0.0F, 0.0F, 0.5F, 0.0F}));
  EXPECT_EQ(gw.input_float(kSetpointsInForce), 0.5F);
  EXPECT_EQ(gw.input_float(kSetpointsInForce + 2), 0.0F);
  EXPECT_NEAR(gw.input_float(kOutputs), 0.5, 0.005) << "xD at its setpoint";
  EXPECT_NEAR(gw.input_float(kOutputs + 2), 0.0, 0.005) << "xB held";
  // At steady state u = G(0)⁻¹ r (CLOSED-LOOP.md): 0.0785, 0.0267 for r = (0.5, 0).
  EXPECT_NEAR(gw.input_float(kApplied), 0.0785, 0.002);
  EXPECT_NEAR(gw.input_float(kApplied + 2), 0.0267, 0.002);
  EXPECT_EQ(gw.input_one(kMode), 2);
}

// The operator's switch to manual: every MV held, status manual, mode off; back in control.
TEST_F(ClosedLoopPlant, ManualHoldsEveryMvAndSaysSo) {
  Master gw(start({"--clock", "lockstep"}));
  ASSERT_TRUE(gw.ok());
  for (int k = 0; k < 30; ++k) ASSERT_TRUE(gw.tick({0.0F, 0.0F, 0.3F, 0.0F}));
  ASSERT_EQ(modbus_write_register(gw.ctx(), kSwitch, 0), 1);
  ASSERT_TRUE(gw.tick({0.0F, 0.0F, 0.3F, 0.0F}));
  const float held = gw.input_float(kApplied);
  EXPECT_NE(held, 0.0F);
  for (int k = 0; k < 10; ++k) ASSERT_TRUE(gw.tick({0.1F, 0.0F, 0.3F, 0.0F}));
  EXPECT_EQ(gw.input_float(kApplied), held) << "manual: the MV holds, the offset is not applied";
  EXPECT_EQ(gw.input_one(kMode), 0);
  EXPECT_EQ(gw.input_one(kStatus), 4);
  EXPECT_EQ(gw.input_one(kStatus + 1), 4);
  ASSERT_EQ(modbus_write_register(gw.ctx(), kSwitch, 1), 1);
  ASSERT_TRUE(gw.tick({0.0F, 0.0F, 0.3F, 0.0F}));
  EXPECT_EQ(gw.input_one(kMode), 2) << "back in control, testing";
  EXPECT_EQ(gw.input_one(kStatus), 0);
}

// The MVs are the controller's: a write to a setpoint register is refused (exception 2).
TEST_F(ClosedLoopPlant, ASetpointWriteIsRefused) {
  Master gw(start({"--clock", "lockstep"}));
  ASSERT_TRUE(gw.ok());
  std::uint16_t r[2];
  from_float(0.2F, r);
  EXPECT_EQ(modbus_write_registers(gw.ctx(), kSetpointRegisters, 2, r), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(gw.holding_float(kSetpointRegisters), 0.0F);
  EXPECT_NE(plant_->stderr_text().find("write refused (exception 2"), std::string::npos);
}

// GIVEN offsets in force and the master silent past the watchdog, THEN every offset register
// reads zero, the controller stays in control, and the plant's own logs say so; an offset
// written while tripped does not apply before the heartbeat moves.
TEST_F(ClosedLoopPlant, TheWatchdogZeroesEveryOffsetAndKeepsTheControllerInControl) {
  Master gw(start({"--clock", "lockstep", "--watchdog-s", "0.3"}));
  ASSERT_TRUE(gw.ok());
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(gw.tick({0.05F, -0.02F, 0.2F, 0.1F}));
  EXPECT_EQ(gw.holding_float(kOffsets), 0.05F);
  EXPECT_EQ(gw.input_one(kMode), 2);
  std::this_thread::sleep_for(600ms);  // silent: the watchdog trips at 0.3 s
  EXPECT_EQ(gw.holding_one(kWatchdogTrips), 1);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(gw.holding_float(kOffsets + 2 * k), 0.0F) << "offset register " << k;
  }
  EXPECT_EQ(gw.input_one(kMode), 1) << "the controller stays in control";
  EXPECT_EQ(gw.input_float(kSetpointsInForce), 0.0F);
  const std::string err = plant_->stderr_text();
  EXPECT_NE(err.find("every test offset returned to zero, the controller stays in control"),
            std::string::npos)
      << err;
  std::vector<std::string> log = controller_log();
  ASSERT_EQ(log.size(), 22U);  // header, 20 samples, the trip
  EXPECT_EQ(log.back().rfind("watchdog,20,20,control,0,0,", 0), 0U)
      << "the trip's row names it, the offsets zero, the mode control: " << log.back();
  std::istringstream row(log.back());
  std::vector<std::string> cells;
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  ASSERT_EQ(cells.size(), 14U);
  EXPECT_EQ(cells[6], cells[8]) << "the applied MV is the controller's move again";
  EXPECT_EQ(cells[7], cells[9]);
  EXPECT_EQ(cells[12], "0") << "setpoints in force back at zero";
  EXPECT_EQ(cells[13], "0");
  EXPECT_EQ(gw.input_float(kApplied), gw.input_float(kMoves));

  // An offset written without the heartbeat moving is set aside: the registers stay zero.
  std::uint16_t r[2];
  from_float(0.07F, r);
  ASSERT_EQ(modbus_write_registers(gw.ctx(), kOffsets, 2, r), 2);
  EXPECT_EQ(gw.holding_float(kOffsets), 0.0F);
  // The heartbeat moves: the master is back, and the sample runs on zero offsets.
  ASSERT_TRUE(gw.tick({0.0F, 0.0F, 0.0F, 0.0F}));
  EXPECT_EQ(gw.input_one(kMode), 1);
  log = controller_log();
  EXPECT_EQ(log.back().rfind("sample,20,20,control,0,0,", 0), 0U) << log.back();
}

// Free-running (real time, sped up): the controller runs every sample without a master.
TEST_F(ClosedLoopPlant, FreeRunningTheControllerStepsOnThePlantsClock) {
  Master gw(start({"--clock", "realtime", "--speedup", "6000"}));  // 10 ms per sample
  ASSERT_TRUE(gw.ok());
  std::uint16_t r[2];
  from_float(0.2F, r);
  ASSERT_EQ(modbus_write_registers(gw.ctx(), kOffsets + 4, 2, r), 2);  // xD's setpoint
  std::this_thread::sleep_for(1500ms);
  EXPECT_EQ(gw.input_float(kSetpointsInForce), 0.2F);
  EXPECT_GT(gw.input_float(kOutputs), 0.05F) << "xD on its way to 0.2";
  EXPECT_EQ(gw.input_one(kMode), 2);
}

// Refused by name, nothing served: a bad controller file, one of another size, a controller
// log without a controller, the closed-loop registers without a controller, input limits.
TEST_F(ClosedLoopPlant, ABadControllerIsRefusedByName) {
  const fs::path bad = dir_.write("bad.toml",
                                  "kind = \"dmc\"\nsample_time_min = 1.0\n[model]\nplant = "
                                  "\"woodberry2x2\"\n[dmc]\nprediction_horizon = 30\n"
                                  "control_horizon = 3\nslack_weigth = 1000.0\n");
  std::ifstream pi_file(kPi);
  std::string pi_text((std::istreambuf_iterator<char>(pi_file)), std::istreambuf_iterator<char>());
  pi_text.replace(pi_text.find("sample_time_min = 1.0"), 21, "sample_time_min = 2.0");
  const fs::path other_t = dir_.write("t2.toml", pi_text);
  const fs::path cfg = dir_.write(
      "plant.toml",
      "[plant]\nlibrary = \"woodberry2x2\"\n[registers]\nheartbeat_address = 104\n"
      "heartbeat_echo_address = 300\nheartbeat_echo_function_code = 4\noffset_address = 10\n"
      "[[registers.setpoints]]\nname = \"R\"\naddress = 100\n[[registers.setpoints]]\nname = "
      "\"S\"\naddress = 102\n[[registers.values]]\nname = \"xD\"\naddress = 200\n"
      "function_code = 4\n[[registers.values]]\nname = \"xB\"\naddress = 202\n"
      "function_code = 4\n");
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases{
      {{"--plant", "woodberry2x2", "--controller", bad.string()},
       "bad.toml:8:16: dmc.slack_weigth = 1000.0 (unknown key), expected one of the known keys"},
      {{"--plant", "alatiqi4x4", "--controller", kPi},
       "woodberry2x2.pi.toml: model.plant = \"woodberry2x2\" (2 inputs, 2 outputs), expected a "
       "model of the served plant's size, 4 inputs and 4 outputs (alatiqi4x4)"},
      {{"--plant", "woodberry2x2", "--controller", other_t.string()},
       "t2.toml: sample_time_min = 2, expected the plant's sample time, 1 min"},
      {{"--plant", "woodberry2x2", "--controller-log", "x.csv"},
       "--controller-log = \"x.csv\", expected a controller to log"},
      {{"--config", cfg.string()},
       "plant.toml: registers.offset_address = 10, expected a controller to serve the "
       "closed-loop registers"},
      {{"--plant", "woodberry2x2", "--controller", kPi, "--input-range", "1"},
       "--input-range = 1, expected no input limits under a controller"},
      // The server table (servers.hpp) says which servers serve a controller's registers.
      {{"--plant", "woodberry2x2", "--controller", kPi, "--can", "vcan0"},
       "expected a server with closed-loop registers (--modbus-tcp or --modbus-rtu): the CAN "
       "frame map has no closed-loop frames"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = c.args;
    if (std::find(args.begin(), args.end(), "--can") == args.end())
      args.insert(args.end(), {"--modbus-tcp", "127.0.0.1:0"});
    PlantRunner plant(args, dir_.path() / "refused.txt");
    EXPECT_FALSE(plant.wait_listening().has_value()) << c.says;
    EXPECT_EQ(plant.wait_exit().value_or(-1), 2) << c.says;
    EXPECT_NE(plant.stderr_text().find(c.says), std::string::npos)
        << "expected: " << c.says << "\ngot: " << plant.stderr_text();
  }
}

// Without --controller the plant is the open-loop one: no closed-loop registers served.
TEST_F(ClosedLoopPlant, WithoutAControllerNothingOfItIsServed) {
  PlantRunner plant(
      {"--plant", "woodberry2x2", "--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep"},
      dir_.path() / "open.txt");
  const auto port = plant.wait_listening();
  ASSERT_TRUE(port.has_value());
  Master gw(*port);
  ASSERT_TRUE(gw.ok());
  EXPECT_EQ(gw.input_one(kMode), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(gw.holding_one(kSwitch), -1);
}

}  // namespace
}  // namespace excite::test
