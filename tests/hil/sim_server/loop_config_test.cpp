// SPDX-License-Identifier: MIT
// One register map for both sides: `excite loop-config` writes plant.toml and gateway.toml;
// the real excite-gateway accepts the gateway side (--dry-run with a real plan), the real
// excite-plant serves the plant side, and the gateway streams a plan to the plant through
// them to the end. The shipped pair (sim/server/examples/loop) is what the generator writes.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <sstream>

#include "firmware/runlog/reader.hpp"
#include "plant_runner.hpp"
#include "sim/server/config_writer.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {
namespace {

using test::PlantRunner;
using test::run_to_completion;
using test::TempDir;
using ::testing::HasSubstr;

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

class LoopConfig : public ::testing::Test {
 protected:
  int excite(const std::vector<std::string>& args) {
    return run_to_completion(EXCITE_CLI_PATH, args, dir_.path() / "excite.txt");
  }
  std::string excite_output() const { return read_text(dir_.path() / "excite.txt"); }

  int gateway(const std::vector<std::string>& args) {
    return run_to_completion(EXCITE_GATEWAY_PATH, args, dir_.path() / "gateway.txt");
  }
  std::string gateway_output() const { return read_text(dir_.path() / "gateway.txt"); }

  std::filesystem::path design(const std::string& plant, const std::string& preset) {
    const auto plan = dir_.path() / (plant + "_" + preset + ".plan");
    EXPECT_EQ(excite({"design", "--plant", plant, "--preset", preset, "-o", plan.string(), "-q"}),
              0)
        << excite_output();
    return plan;
  }

  TempDir dir_;
};

TEST_F(LoopConfig, GeneratedPairParsesOnBothSides) {
  for (const std::string plant : {"alatiqi4x4", "woodberry2x2", "colaA", "pilot15"}) {
    const auto out = dir_.path() / plant;
    ASSERT_EQ(excite({"loop-config", "--plant", plant, "--port", "1502", "-o", out.string()}), 0)
        << excite_output();
    // The gateway side: the real excite-gateway checks it against a real plan, opens nothing.
    const auto plan = design(plant, "prbsUnc");
    EXPECT_EQ(gateway({"--config", (out / "gateway.toml").string(), "--plan", plan.string(),
                       "--dry-run"}),
              0)
        << plant << ": " << gateway_output();
    // The plant side: the real excite-plant serves it in lock-step.
    PlantRunner server({"--config", (out / "plant.toml").string(), "--modbus-tcp", "127.0.0.1:0",
                        "--clock", "lockstep"},
                       dir_.path() / "plant.txt");
    EXPECT_TRUE(server.wait_listening()) << plant << ": " << server.stderr_text();
    EXPECT_EQ(server.stop(SIGTERM), 0);
  }
}

TEST_F(LoopConfig, GatewayStreamsAPlanToThePlantThroughTheGeneratedPair) {
  // GIVEN the plant side served on an ephemeral port, and the gateway side written for it
  const auto out = dir_.path() / "loop";
  ASSERT_EQ(excite({"loop-config", "--plant", "woodberry2x2", "-o", out.string()}), 0);
  const auto plant_log = dir_.path() / "plant.csv";
  PlantRunner server({"--config", (out / "plant.toml").string(), "--modbus-tcp", "127.0.0.1:0",
                      "--clock", "lockstep", "--log", plant_log.string()},
                     dir_.path() / "plant.txt");
  const auto port = server.wait_listening();
  ASSERT_TRUE(port) << server.stderr_text();
  ASSERT_EQ(excite({"loop-config", "--plant", "woodberry2x2", "--port", std::to_string(*port),
                    "--period-s", "0.002", "-o", out.string()}),
            0);
  const auto plan = design("woodberry2x2", "prbsUnc");
  // WHEN the real gateway streams the plan, in lock-step as a HIL bench runs it
  const auto run_log = dir_.path() / "run.csv";
  ASSERT_EQ(gateway({"--config", (out / "gateway.toml").string(), "--plan", plan.string(), "--log",
                     run_log.string(), "--start", "--clock", "lockstep"}),
            0)
      << gateway_output();
  // THEN it completes, and the plant took one sample per heartbeat the gateway wrote
  ASSERT_EQ(server.stop(SIGTERM), 0) << server.stderr_text();
  const runlog::ReadResult gw = runlog::read_run_log(run_log.string());
  ASSERT_TRUE(gw.ok()) << gw.error->to_string();
  const runlog::ReadResult pl = runlog::read_run_log(plant_log.string());
  ASSERT_TRUE(pl.ok()) << pl.error->to_string();
  EXPECT_GT(gw.log.rows(), 100U);
  // One plant sample per gateway tick, in lock-step: the same rows, the setpoints the
  // gateway wrote as the float32 registers carry them, and the gateway read exactly the
  // plant's outputs (likewise as float32).
  ASSERT_EQ(pl.log.rows(), gw.log.rows());
  for (std::size_t k = 0; k < gw.log.rows(); ++k) {
    for (std::size_t i = 0; i < 2; ++i) {
      ASSERT_EQ(static_cast<double>(static_cast<float>(gw.log.u[i][k])), pl.log.u[i][k])
          << "row " << k;
    }
    for (std::size_t j = 0; j < 2; ++j) {
      ASSERT_EQ(gw.log.dy[j][k], static_cast<double>(static_cast<float>(pl.log.dy[j][k])))
          << "row " << k;
    }
  }
  EXPECT_THAT(server.stderr_text(), HasSubstr(" 0 values did not fit their registers"));
}

TEST_F(LoopConfig, ShippedPairIsWhatTheGeneratorWritesAndWorks) {
  const std::filesystem::path shipped = EXCITE_LOOP_EXAMPLE_DIR;
  const auto out = dir_.path() / "loop";
  ASSERT_EQ(excite({"loop-config", "--plant", "alatiqi4x4", "-o", out.string()}), 0);
  EXPECT_EQ(read_text(out / "plant.toml"), read_text(shipped / "plant.toml"));
  EXPECT_EQ(read_text(out / "gateway.toml"), read_text(shipped / "gateway.toml"));
  const auto plan = design("alatiqi4x4", "prbsUnc");
  EXPECT_EQ(gateway({"--config", (shipped / "gateway.toml").string(), "--plan", plan.string(),
                     "--dry-run"}),
            0)
      << gateway_output();
}

TEST_F(LoopConfig, BadNumbersAreRefusedByName) {
  EXPECT_NE(excite({"loop-config", "--plant", "alatiqi4x4", "--input-range", "nan", "-o",
                    (dir_.path() / "x").string()}),
            0);
  EXPECT_THAT(excite_output(), HasSubstr("--input-range: nan, expected a finite number >= 0"));
  EXPECT_NE(excite({"loop-config", "--plant", "nosuch", "-o", (dir_.path() / "x").string()}), 0);
  EXPECT_THAT(excite_output(), HasSubstr("nosuch"));
}

// The plant side carries the plant's own controller: a watchdog (3 s unless told, and at
// least two gateway periods: without period_s the sample time, 1 min here, so 120 s) and
// input limits equal to the gateway's min/max, number for number.
TEST_F(LoopConfig, PlantSideHasAWatchdogAndTheGatewaysLimits) {
  const auto out = dir_.path() / "wd";
  ASSERT_EQ(
      excite({"loop-config", "--plant", "woodberry2x2", "--input-range", "2", "-o", out.string()}),
      0)
      << excite_output();
  const ServerConfig plant = load_server_config(out / "plant.toml");
  EXPECT_EQ(plant.plant.watchdog_s, 120.0);
  ASSERT_EQ(plant.plant.input_min.size(), 2U);
  const std::string gw = read_text(out / "gateway.toml");
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_THAT(gw, HasSubstr("\nmin = " + toml_number(plant.plant.input_min[i]) + "\n"));
    EXPECT_THAT(gw, HasSubstr("\nmax = " + toml_number(plant.plant.input_max[i]) + "\n"));
    EXPECT_NEAR(plant.plant.input_max[i] - plant.plant.input_min[i], 4.0, 1e-6);
  }
  ASSERT_EQ(excite({"loop-config", "--plant", "woodberry2x2", "--input-range", "2", "--watchdog-s",
                    "0", "-o", out.string()}),
            0);
  EXPECT_EQ(load_server_config(out / "plant.toml").plant.watchdog_s, 0.0) << "0: off";
  for (const std::string bad : {"nan", "-1"}) {
    EXPECT_NE(
        excite({"loop-config", "--plant", "woodberry2x2", "--watchdog-s", bad, "-o", out.string()}),
        0);
    EXPECT_THAT(excite_output(), HasSubstr("--watchdog-s: " + bad + ", expected"));
  }
}

}  // namespace
}  // namespace excite::sim::server
