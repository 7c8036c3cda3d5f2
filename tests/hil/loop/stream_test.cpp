// SPDX-License-Identifier: MIT
// The gateway streams whole plans to excite-plant in lock-step over Modbus TCP on loopback,
// and the result is the simulation: the gateway's run log equals `excite simulate` of the
// same plan, plant and noise seed, sample for sample, to the resolution of the float32
// registers the default map uses.
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

// float32 carries 24 significant bits: one rounding of a value of size |v| moves it by at
// most |v|·2⁻²⁴. The plant sees float32(u) and the gateway reads float32(y), so each logged
// output differs from the double-precision simulation by its own rounding plus the response
// to the input roundings, bounded by gain · 2⁻²⁴ · max|u|. A mis-mapped register or a
// one-sample shift is orders of magnitude larger (checked below, so the test can fail).

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b,
                          std::size_t rows, std::size_t shift = 0) {
  double worst = 0.0;
  for (std::size_t k = shift; k < rows; ++k) worst = std::max(worst, std::abs(a[k] - b[k - shift]));
  return worst;
}

class Stream : public LoopTest {
 protected:
  // The loop over a serial line: socat makes a pty pair, excite-plant serves plant.toml
  // with --modbus-rtu on one end, and gateway.toml (from loop-config) is turned into the
  // RTU device on the other end — the same register map, another transport.
  void start_rtu_loop(const std::string& plant, const std::string& config_args) {
    const fs::path plant_end = path("plant-tty");
    const fs::path gateway_end = path("gateway-tty");
    socat_ = std::make_unique<PlantRunner>(
        "/usr/bin/socat",
        std::vector<std::string>{"pty,raw,echo=0,link=" + plant_end.string(),
                                 "pty,raw,echo=0,link=" + gateway_end.string()},
        path("socat.stderr"));
    for (int i = 0; i < 250 && !(fs::exists(plant_end) && fs::exists(gateway_end)); ++i) {
      std::this_thread::sleep_for(20ms);
    }
    ASSERT_TRUE(fs::exists(gateway_end)) << socat_->stderr_text();
    loop_config(plant, 1502, config_args);
    plant_ = std::make_unique<PlantRunner>(
        std::vector<std::string>{"--config", path("plant.toml").string(), "--modbus-rtu",
                                 plant_end.string(), "--baud", "115200", "--clock", "lockstep",
                                 "--log", path("plant.csv").string()},
        path("plant.stderr"));
    ASSERT_TRUE(plant_->wait_listening().has_value()) << plant_->stderr_text();
    std::ifstream in(path("gateway.toml"));
    std::ostringstream rewritten;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("transport = ", 0) == 0) {
        rewritten << "transport = \"modbus-rtu\"\nserial_port = \"" << gateway_end.string()
                  << "\"\nbaud = 115200\n";
      } else if (line.rfind("host = ", 0) != 0 && line.rfind("port = ", 0) != 0) {
        rewritten << line << "\n";
      }
    }
    in.close();
    std::ofstream(path("gateway.toml")) << rewritten.str();
  }

  std::unique_ptr<PlantRunner> socat_;

  // GIVEN a plan and a plant; WHEN the real gateway streams it to the real plant server in
  // lock-step and `excite simulate` runs the same plan, plant, noise and seed;
  // THEN both logs agree row for row (within float32), and so does the plant's own log.
  // Over Modbus RTU when `rtu`: the plant on one end of a pseudo-terminal pair (socat),
  // the gateway on the other.
  void expect_stream_equals_simulation(const std::string& plant, const std::string& preset,
                                       const std::string& noise, double output_tolerance,
                                       bool rtu = false) {
    const fs::path plan = design(plant, preset);
    if (rtu) {
      start_rtu_loop(plant, "--noise-var " + noise + " --seed 7");
    } else {
      start_loop(plant, "--noise-var " + noise + " --seed 7");
    }
    auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
    const auto rc = gw->wait(300s);
    ASSERT_TRUE(rc.has_value()) << "the gateway did not finish";
    ASSERT_EQ(*rc, 0) << gw->err();
    const runlog::RunLog plant_log = stop_plant_and_read_its_log();

    const std::string simulate = std::string(EXCITE_TOOL) + " simulate " + plan.string() +
                                 " --plant " + plant + " --noise-var " + noise + " --seed 7 -o " +
                                 path("sim.csv").string() + " > /dev/null";
    ASSERT_TRUE(shell(simulate)) << simulate;
    const runlog::RunLog sim = read_log_or_fail(path("sim.csv"));
    const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));

    // The gateway logs every tick: the table's rows first, then the ramp-out to the
    // baseline; the plant takes one sample per tick.
    const std::size_t n = sim.rows();
    ASSERT_GE(gwl.rows(), n);
    ASSERT_EQ(plant_log.rows(), gwl.rows());
    ASSERT_EQ(gwl.du.size(), sim.du.size());
    ASSERT_EQ(gwl.dy.size(), sim.dy.size());
    for (std::size_t i = 0; i < sim.du.size(); ++i) {
      // The gateway logs du = (baseline + table) − baseline: exact for a zero baseline, a
      // double rounding of the absolute setpoint otherwise.
      EXPECT_LE(max_abs_difference(gwl.du[i], sim.du[i], n), 0x1p-52 * max_abs(gwl.u[i]))
          << "du " << sim.input_names[i];
      // What reached the plant is the float32 of the absolute setpoint the gateway wrote.
      EXPECT_LE(max_abs_difference(plant_log.du[i], gwl.du[i], gwl.rows()),
                kFloat32Epsilon * max_abs(plant_log.u[i]) * 2)
          << "input " << sim.input_names[i] << " as the plant received it";
    }
    for (std::size_t j = 0; j < sim.dy.size(); ++j) {
      const double diff = max_abs_difference(gwl.dy[j], sim.dy[j], n);
      EXPECT_LE(diff, output_tolerance) << "output " << sim.output_names[j];
      // Power to tell: the same logs shifted by one sample differ by far more.
      EXPECT_GT(max_abs_difference(gwl.dy[j], sim.dy[j], n, 1), 10 * output_tolerance)
          << "output " << sim.output_names[j];
      EXPECT_LE(max_abs_difference(plant_log.dy[j], gwl.dy[j], gwl.rows()),
                kFloat32Epsilon * (max_abs(gwl.dy[j]) + 1.0) * 2)
          << "output " << sim.output_names[j] << " as the plant logged it";
    }
    // The run ends where it began, on the plant's side.
    for (std::size_t i = 0; i < plant_log.du.size(); ++i) {
      EXPECT_LE(std::abs(plant_log.du[i].back()), kFloat32Epsilon * max_abs(plant_log.u[i]) * 2)
          << "input " << plant_log.input_names[i];
    }
  }
};

TEST_F(Stream, CaseStudyPlanInLockstepEqualsExciteSimulateSampleForSample) {
  // alatiqi4x4 gains up to ~10, inputs up to ~1: input rounding ≤ 10 · 2⁻²⁴ ≈ 6e-7,
  // output rounding ≤ 2⁻²⁴ · |y| ≈ 1e-7.
  expect_stream_equals_simulation("alatiqi4x4", "prbsSimDir", "5e-4", 2e-6);
}

TEST_F(Stream, OverModbusRtuThroughAPtyPairEqualsExciteSimulateToo) {
  if (!fs::exists("/usr/bin/socat")) GTEST_SKIP() << "socat is not installed (Debian: socat)";
  // woodberry2x2: gains up to 19, inputs up to ~0.1 after sizing: ≤ 2e-7 from rounding.
  expect_stream_equals_simulation("woodberry2x2", "prbsUnc", "5e-4", 2e-6, true);
}

TEST_F(Stream, NonlinearColumnColaAStreamsAWholeCaseStudyPlanLive) {
  // colaA is served in absolute units: flows near 3 kmol/min (float32 rounding 2e-7) and
  // compositions near 0.99 (6e-8); with gains up to ~2 mol/mol per kmol/min that bounds
  // the difference by ~6e-7. The stepped and the batch integrations agree to far less.
  expect_stream_equals_simulation("colaA", "prbsSimDir", "0", 1e-6);
}

}  // namespace
}  // namespace excite::test
