// SPDX-License-Identifier: MIT
// Hardware-in-the-loop on the target architecture: the excite-gateway of this build (under
// qemu-user in a cross build) streams a designed alatiqi4x4 plan over loopback Modbus TCP to
// the native excite-plant in lock-step, and the assertions are made on the plant's side: its
// run log shows the excitation the gateway's log says it wrote, sample for sample. A bad
// configuration (missing plan, unreadable configuration, setpoint limits missing) is refused
// with one line naming the problem, before anything reaches the field: the plant logs no
// sample.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../gateway/gateway_process.hpp"
#include "firmware/runlog/reader.hpp"

namespace excite::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr double kU0[4] = {10.0, 20.0, 30.0, 40.0};  // sim/server/examples/alatiqi4x4.toml

// The gateway's configuration for the example plant's register map (word orders, the int16
// scaling of u4, readbacks on the setpoint registers, the heartbeat echo). `setpoint_limits`
// false leaves min/max out of setpoints[0] (a device configuration without limits).
std::string gateway_config(std::uint16_t port, bool setpoint_limits = true) {
  std::ostringstream t;
  t << "[gateway]\nplant = \"alatiqi4x4 on excite-plant\"\nperiod_s = 0.005\nramp_s = 0.02\n"
       "comm_fail_limit = 5\nheartbeat_max_lag_s = 2.0\nlog_ring = 16384\n"
       "realtime_priority = 0\n\n[device]\ntransport = \"tcp\"\nhost = \"127.0.0.1\"\nport = "
    << port << "\nunit_id = 1\nresponse_timeout_ms = 1000\n\n[map]\nheartbeat_address = 108\n";
  const char* names[] = {"u1", "u2", "u3", "u4"};
  const char* types[] = {
      "type = \"float32\"\nword_order = \"CDAB\"\n", "type = \"float32\"\nword_order = \"ABCD\"\n",
      "type = \"float32\"\nword_order = \"BADC\"\n",
      "type = \"int16\"\neng_min = 0.0\neng_max = 100.0\nraw_min = 0\nraw_max = 27648\n"};
  for (int i = 0; i < 4; ++i) {
    t << "\n[[setpoints]]\nname = \"" << names[i]
      << "\"\nunit = \"kmol/min\"\naddress = " << 100 + 2 * i << '\n'
      << types[i];
    if (setpoint_limits || i != 0) t << "min = " << kU0[i] - 5 << "\nmax = " << kU0[i] + 5 << '\n';
    t << "max_move = 1.0\nreadback = \"" << names[i] << "_sp\"\n";
  }
  const char* outputs[] = {
      "address = 200\nfunction_code = 4\ntype = \"float32\"\nword_order = \"CDAB\"\n",
      "address = 202\nfunction_code = 4\ntype = \"float32\"\nword_order = \"DCBA\"\n",
      "address = 204\nfunction_code = 3\ntype = \"float32\"\nword_order = \"ABCD\"\n",
      // y4 as the plant serves it (sim/server/examples/alatiqi4x4.toml): int16 over [-40, 40]
      "address = 206\nfunction_code = 4\ntype = \"int16\"\neng_min = -40.0\neng_max = 40.0\n"};
  for (int j = 0; j < 4; ++j) {
    t << "\n[[values]]\nname = \"y" << j + 1 << "\"\n" << outputs[j];
  }
  for (int i = 0; i < 4; ++i) {
    t << "\n[[values]]\nname = \"" << names[i]
      << "_sp\"\nrole = \"readback\"\naddress = " << 100 + 2 * i << "\nfunction_code = 3\n"
      << types[i];
  }
  t << "\n[[values]]\nname = \"hb_echo\"\nrole = \"heartbeat_echo\"\naddress = 300\n"
       "function_code = 4\ntype = \"uint16\"\neng_min = 0\neng_max = 65535\n";
  return t.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The gateway's stderr minus qemu's own chatter (there is none today; kept honest by the
// one-line assertions below, which would count it).
std::vector<std::string> stderr_lines(const GatewayProcess& p) {
  return lines_of(p.err());
}

class CrossGatewayPlant : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(fs::exists(EXCITE_PLANT))
        << EXCITE_PLANT << " is missing: build the native tools first (cmake --build --preset "
        << "default --target excite-plant excite), or set EXCITE_NATIVE_BIN_DIR";
    dir_ = fs::temp_directory_path() /
           ("excite_cross_hil_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    plant_log_ = (dir_ / "plant.csv").string();
    const std::string plant_config =
        std::string(EXCITE_SOURCE_DIR) + "/sim/server/examples/alatiqi4x4.toml";
    plant_.emplace(EXCITE_PLANT,
                   std::vector<std::string>{"--config", plant_config, "--port", "0", "--lockstep",
                                            "--log", plant_log_},
                   (dir_ / "plant").string());
    const auto until = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < until) {
      const std::string out = plant_->out();
      const auto eol = out.find('\n');
      if (eol != std::string::npos) {
        const std::string first = out.substr(0, eol);
        ASSERT_EQ(first.rfind("listening 127.0.0.1:", 0), 0U) << first;
        port_ = static_cast<std::uint16_t>(std::stoi(first.substr(first.rfind(':') + 1)));
        return;
      }
      ASSERT_FALSE(plant_->wait(0ms).has_value()) << "excite-plant exited: " << plant_->err();
      std::this_thread::sleep_for(10ms);
    }
    FAIL() << "excite-plant printed no listening line in 10 s: " << plant_->err();
  }

  void TearDown() override {
    if (plant_) {
      plant_->signal(SIGTERM);
      plant_->wait(5s);
    }
    std::error_code ignored;
    if (!HasFailure()) fs::remove_all(dir_, ignored);
  }

  // Stops the plant (SIGTERM: log flushed) and reads its run log.
  runlog::RunLog stop_plant_and_read_log() {
    plant_->signal(SIGTERM);
    const auto rc = plant_->wait(10s);
    EXPECT_EQ(rc, std::optional<int>(0)) << plant_->err();
    runlog::ReadOptions options;
    options.min_rows = 0;
    const runlog::ReadResult r = runlog::read_run_log(plant_log_, options);
    EXPECT_TRUE(r.ok()) << (r.error ? r.error->to_string() : "");
    return r.log;
  }

  // The gateway binary of this build, under the emulator in a cross build.
  GatewayProcess start_gateway(const std::vector<std::string>& args) {
    // EXCITE_EMULATOR: "program|arg|..." (CMAKE_CROSSCOMPILING_EMULATOR), empty when native.
    std::vector<std::string> all;
    std::string binary = EXCITE_GATEWAY;
    const std::string emulator = EXCITE_EMULATOR;
    if (!emulator.empty()) {
      std::vector<std::string> words;
      std::istringstream in(emulator);
      for (std::string w; std::getline(in, w, '|');) words.push_back(w);
      binary = words.front();
      all.assign(words.begin() + 1, words.end());
      all.push_back(EXCITE_GATEWAY);
    }
    all.insert(all.end(), args.begin(), args.end());
    return GatewayProcess(binary, all, (dir_ / "gateway").string());
  }

  std::string design_plan() {
    const std::string plan = (dir_ / "alatiqi4x4.plan").string();
    const std::string cmd =
        std::string(EXCITE_TOOL) + " design -q --plant alatiqi4x4 --preset prbsUnc -o " + plan;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return plan;
  }

  fs::path dir_;
  std::string plant_log_;
  std::optional<GatewayProcess> plant_;
  std::uint16_t port_ = 0;
};

// Largest |gateway[r] - plant[r + 1]| over every gateway row, inf when the plant does not
// have exactly one row more: no realignment. The plant's row 0 is its state before the first
// write; each heartbeat write then makes one sample, so gateway row r is plant row r + 1.
double row_difference(const std::vector<double>& gateway, const std::vector<double>& plant) {
  if (plant.size() != gateway.size() + 1) return INFINITY;
  double worst = 0.0;
  for (std::size_t r = 0; r < gateway.size(); ++r) {
    worst = std::max(worst, std::abs(gateway[r] - plant[r + 1]));
  }
  return worst;
}

TEST_F(CrossGatewayPlant, StreamsThePlanAndThePlantReceivesEverySample) {
  const std::string plan = design_plan();
  const std::string config = (dir_ / "gateway.toml").string();
  std::ofstream(config) << gateway_config(port_);
  const std::string gw_log = (dir_ / "gateway.csv").string();
  const auto started = std::chrono::steady_clock::now();
  GatewayProcess gw =
      start_gateway({"--config", config, "--plan", plan, "--log", gw_log, "--start"});
  // Footprint figure (README.md, "Cross builds"): process start to the "armed" line, i.e.
  // configuration, plan, table, connection and the first read, under the emulator if any.
  while (gw.err().find("armed (") == std::string::npos && !gw.wait(0ms)) {
    std::this_thread::sleep_for(2ms);
  }
  const auto armed_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::steady_clock::now() - started);
  const auto rc = gw.wait(400s);
  ASSERT_EQ(rc, std::optional<int>(0)) << gw.err();
  EXPECT_NE(gw.err().find("armed (4 setpoints"), std::string::npos) << gw.err();
  std::printf("footprint: start to armed %lld ms; gateway stderr:\n%s",
              static_cast<long long>(armed_ms.count()), gw.err().c_str());

  const runlog::ReadResult g = runlog::read_run_log(gw_log);
  ASSERT_TRUE(g.ok()) << g.error->to_string();
  const runlog::RunLog p = stop_plant_and_read_log();
  ASSERT_EQ(p.u.size(), 4U);
  ASSERT_EQ(g.log.u.size(), 4U);
  // One plant sample per heartbeat change, i.e. per tick the gateway wrote (a late tick's
  // skipped grid points are no write), after the plant's row 0 (before the first write).
  EXPECT_EQ(p.rows(), g.log.rows() + 1);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto [lo, hi] = std::minmax_element(p.u[i].begin(), p.u[i].end());
    EXPECT_GT(*hi - *lo, 0.0) << "input " << i << ": the plant saw no excitation";
    // Inside the gateway's setpoint limits (baseline ± 5) all along, and back at the
    // baseline at the end (completed -> returning -> safe writes the baseline).
    EXPECT_LE(std::max(*hi - kU0[i], kU0[i] - *lo), 5.0) << "input " << i;
    EXPECT_NEAR(p.u[i].back(), kU0[i], 0.01) << "input " << i << " did not end at baseline";
    // float32 rounding (2^-24 relative), and u4's int16 scaling (100 / 27648 per count).
    const double tolerance = i == 3 ? 100.0 / 27648.0 : 0x1p-23 * (kU0[i] + 5.0);
    EXPECT_LE(row_difference(g.log.u[i], p.u[i]), tolerance) << "input " << i;
  }
  // The outputs the gateway read are the plant's, row for row: float32 registers (y1..y3),
  // and y4 an int16 over [-40, 40] (80 / 65535 per count).
  ASSERT_EQ(p.dy.size(), 4U);
  ASSERT_EQ(g.log.dy.size(), 4U);
  for (std::size_t j = 0; j < 4; ++j) {
    double scale = 0.0;
    for (double v : p.dy[j]) scale = std::max(scale, std::abs(v));
    const double tolerance = j == 3 ? 80.0 / 65535.0 : 0x1p-23 * (scale + 1.0);
    const double d = row_difference(g.log.dy[j], p.dy[j]);
    std::printf("output %zu: largest row difference %.3g (tolerance %.3g)\n", j, d, tolerance);
    EXPECT_LE(d, tolerance) << "output " << j;
  }
}

// Each refusal: the given exit code, exactly one stderr line containing `needle`, and not one
// plant sample (nothing was written: the lock-step plant samples on every heartbeat write).
void expect_refused(GatewayProcess& gw, int code, const std::string& needle) {
  const auto rc = gw.wait(60s);
  ASSERT_EQ(rc, std::optional<int>(code)) << gw.err();
  const std::vector<std::string> lines = stderr_lines(gw);
  ASSERT_EQ(lines.size(), 1U) << gw.err();
  EXPECT_EQ(lines[0].rfind("excite-gateway: ", 0), 0U) << lines[0];
  EXPECT_NE(lines[0].find(needle), std::string::npos) << lines[0];
}

TEST_F(CrossGatewayPlant, MissingPlanIsRefusedWithOneLineAndNothingWritten) {
  const std::string config = (dir_ / "gateway.toml").string();
  std::ofstream(config) << gateway_config(port_);
  const std::string missing = (dir_ / "no-such.plan").string();
  GatewayProcess gw =
      start_gateway({"--config", config, "--plan", missing, "--log", (dir_ / "gw.csv").string()});
  expect_refused(gw, 3, missing + ": cannot open the plan file");
  EXPECT_FALSE(fs::exists(dir_ / "gw.csv"));
  EXPECT_EQ(stop_plant_and_read_log().rows(), 0U);
}

TEST_F(CrossGatewayPlant, UnreadableConfigurationIsRefusedWithOneLineAndNothingWritten) {
  const std::string plan = design_plan();
  const std::string config = (dir_ / "gateway.toml").string();
  std::ofstream(config) << gateway_config(port_);
  fs::permissions(config, fs::perms::none);
  if (std::ifstream(config).good()) {  // root reads it anyway: use a directory instead
    fs::remove(config);
    fs::create_directory(config);
  }
  GatewayProcess gw =
      start_gateway({"--config", config, "--plan", plan, "--log", (dir_ / "gw.csv").string()});
  expect_refused(gw, 2, config);
  EXPECT_EQ(stop_plant_and_read_log().rows(), 0U);
}

TEST_F(CrossGatewayPlant, SetpointLimitsMissingIsRefusedWithOneLineAndNothingWritten) {
  const std::string plan = design_plan();
  const std::string config = (dir_ / "gateway.toml").string();
  std::ofstream(config) << gateway_config(port_, /*setpoint_limits=*/false);
  GatewayProcess gw =
      start_gateway({"--config", config, "--plan", plan, "--log", (dir_ / "gw.csv").string()});
  expect_refused(gw, 2, "setpoints[0].min");
  EXPECT_EQ(stop_plant_and_read_log().rows(), 0U);
}

}  // namespace
}  // namespace excite::test
