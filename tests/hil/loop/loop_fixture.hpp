// SPDX-License-Identifier: MIT
#pragma once
// The gateway in the loop, as it runs: the real excite-plant process serving a plant over a
// real socket, the real excite-gateway process streaming a plan from `excite design` to
// it through the configuration `excite loop-config` wrote for that plant server, and
// `excite simulate` as the oracle. Tests assert on the plant's side (its own run log) as
// well as on the gateway's exit code and log.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "../gateway/gateway_process.hpp"
#include "firmware/runlog/reader.hpp"
#include "plant_runner.hpp"

namespace excite::test {

namespace fs = std::filesystem;

/// Runs a command line through the shell; true when it exited 0.
inline bool shell(const std::string& line) {
  return std::system(line.c_str()) == 0;
}

inline runlog::RunLog read_log_or_fail(const fs::path& path) {
  const runlog::ReadResult r = runlog::read_run_log(path.string());
  EXPECT_TRUE(r.ok()) << path << ": " << (r.error ? r.error->to_string() : "");
  return r.log;
}

/// One folder per test: plans, the configuration pair, the plant server, the gateway.
class LoopTest : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return tmp_.path() / name; }

  /// `excite design -q --plant P --preset X`; returns the plan's path.
  fs::path design(const std::string& plant, const std::string& preset) {
    const fs::path plan = path(preset + ".plan");
    const std::string line = std::string(EXCITE_TOOL) + " design -q --plant " + plant +
                             " --preset " + preset + " -o " + plan.string() + " > " +
                             path("design.out").string();
    EXPECT_TRUE(shell(line)) << line;
    return plan;
  }

  /// `excite loop-config --plant P --port PORT ARGS…`: plant.toml and gateway.toml, one
  /// register map for both sides.
  void loop_config(const std::string& plant, std::uint16_t port, const std::string& args) {
    const std::string line = std::string(EXCITE_TOOL) + " loop-config --plant " + plant +
                             " --port " + std::to_string(port) + " " + args + " -o " +
                             tmp_.path().string() + " > " + path("config.out").string();
    ASSERT_TRUE(shell(line)) << line;
  }

  /// The loop for `plant`: loop-config writes the pair; excite-plant serves plant.toml on an
  /// ephemeral loopback port (plus `plant_args`, e.g. faults), logging every sample to
  /// plant.csv; gateway.toml is then written again for that port. Returns the port.
  std::uint16_t start_loop(const std::string& plant, const std::string& config_args = "",
                           const std::vector<std::string>& plant_args = {"--clock", "lockstep"}) {
    loop_config(plant, 1502, config_args);
    const std::uint16_t port = start_plant(plant_args, 0);
    loop_config(plant, port, config_args);
    return port;
  }

  /// excite-plant --config plant.toml --modbus-tcp 127.0.0.1:PORT --log plant.csv ARGS…
  /// (PORT 0: ephemeral); waits for its "listening" line and returns the port.
  std::uint16_t start_plant(const std::vector<std::string>& plant_args, std::uint16_t port,
                            const std::string& log = "plant.csv") {
    std::vector<std::string> args = {"--config",     path("plant.toml").string(),
                                     "--modbus-tcp", "127.0.0.1:" + std::to_string(port),
                                     "--log",        path(log).string()};
    args.insert(args.end(), plant_args.begin(), plant_args.end());
    plant_ = std::make_unique<PlantRunner>(args, path("plant.stderr"));
    const auto listening = plant_->wait_listening();
    EXPECT_TRUE(listening.has_value()) << plant_->stderr_text();
    return listening.value_or(0);
  }

  /// The real gateway with gateway.toml, `plan` and log gw.csv, plus `extra` arguments.
  std::unique_ptr<GatewayProcess> start_gateway(const fs::path& plan,
                                                std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--config", path("gateway.toml").string(),
                                     "--plan",   plan.string(),
                                     "--log",    path("gw.csv").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return std::make_unique<GatewayProcess>(EXCITE_GATEWAY, args, path("gw").string());
  }

  /// Stops the plant server (SIGTERM: it flushes its log) and reads its run log.
  runlog::RunLog stop_plant_and_read_its_log(const std::string& log = "plant.csv") {
    EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0) << plant_->stderr_text();
    return read_log_or_fail(path(log));
  }

  TempDir tmp_;
  std::unique_ptr<PlantRunner> plant_;
};

}  // namespace excite::test
