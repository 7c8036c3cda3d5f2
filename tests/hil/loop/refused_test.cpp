// SPDX-License-Identifier: MIT
// Issue 28 item 1, with the real gateway and the real plant server over a real socket: a
// device that refuses a write is not a lost link.
//  - excite-plant's own input limits (--input-range 0.05) tighter than the gateway's (±2)
//    answer the first write beyond them with exception 3: the gateway stops the excitation at
//    once, ramps out and confirms the baseline (the plant's own log), exits 14 naming the
//    setpoint, its register, the value and the exception, and counts exceptions by code
//    (before: "communication lost", suspended, and in lock-step with no suspension timeout it
//    spun until killed);
//  - exception 4 (server device failure) stays transient: the run completes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

constexpr double kPlantRange = 0.05;  // the plant's own limits: baseline ± 0.05

class Refused : public LoopTest {
 protected:
  void start(const std::vector<std::string>& plant_faults) {
    std::vector<std::string> plant_args = {"--clock", "lockstep"};
    plant_args.insert(plant_args.end(), plant_faults.begin(), plant_faults.end());
    start_loop(kPlant, "--input-range 2 --period-s 0.005", plant_args);
    plan_ = design(kPlant, "prbsUnc");
    // A ramp-in of 100 ticks: u1 (PRBS ±0.069) crosses the plant's 0.05 at about tick 72,
    // so the plant's log shows the excitation, the refusal, and the way back.
    const fs::path p = path("gateway.toml");
    std::string text = slurp(p);
    const std::string from = "comm_fail_limit = 3";
    text.replace(text.find(from), from.size(), "comm_fail_limit = 3\nramp_s = 0.5");
    std::ofstream(p) << text;
  }
  fs::path plan_;
};

// GIVEN excite-plant refusing setpoints beyond baseline ± 0.05 (exception 3), the gateway in
// lock-step with no suspension timeout (what `excite loop-config` writes)
// THEN exit 14 within seconds, the message names u1, register 100 float32 ABCD, the value
//      and exception 3; the plant's own log stays inside its limits and ends at its baseline.
TEST_F(Refused, ADeviceThatRefusesAWriteStopsTheRunWithItsOwnExitCode) {
  start({"--input-range", "0.05"});
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << "the gateway did not stop: " << gw->err().substr(0, 2000);
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 14) << err;
  EXPECT_NE(err.find("fault: device refused setpoints u1 = "), std::string::npos) << err;
  EXPECT_NE(err.find("(register 100 float32 ABCD)"), std::string::npos) << err;
  EXPECT_NE(err.find(": exception 3, illegal data value — the device's own limits?"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("fault: the device refused a request"), std::string::npos) << err;
  EXPECT_NE(err.find("exception replies by code: 3 (illegal data value) 1\n"), std::string::npos)
      << err;
  // The value named is the one the plant refused: beyond its limits.
  const std::size_t at = err.find("setpoints u1 = ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_GT(std::abs(std::stod(err.substr(at + 15))), kPlantRange) << err;

  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(log.rows(), 50U);
  // The excitation stopped: the row that says `aborted` comes early (the confirmation that
  // follows takes two readbacks a hold interval apart: 2 × the response timeout).
  std::size_t aborted_row = log.rows();
  for (std::size_t r = 0; r < log.rows() && aborted_row == log.rows(); ++r) {
    if (log.state[r] == runlog::RunState::aborted) aborted_row = r;
  }
  EXPECT_LT(aborted_row, 300U) << "the excitation went on after the refusal";
  EXPECT_EQ(log.state.back(), runlog::RunState::safe);

  const runlog::RunLog plant = stop_plant_and_read_its_log();
  EXPECT_NE(plant_->stderr_text().find("1 writes refused for the input limits"), std::string::npos)
      << plant_->stderr_text();
  ASSERT_GT(plant.rows(), 50U);
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    double peak = 0.0;
    for (double x : plant.du[i]) peak = std::max(peak, std::abs(x));
    EXPECT_LE(peak, kPlantRange + 1e-6) << plant.input_names[i];
    EXPECT_LE(std::abs(plant.du[i].back()), 1e-6) << plant.input_names[i] << " not at baseline";
  }
  // Excited first (u1 close to its limit), then ramped back: values strictly in between.
  const std::vector<double>& du1 = plant.du[0];
  const auto peak_at = static_cast<std::size_t>(
      std::max_element(du1.begin(), du1.end(),
                       [](double a, double b) { return std::abs(a) < std::abs(b); }) -
      du1.begin());
  EXPECT_GT(std::abs(du1[peak_at]), 0.8 * kPlantRange);
  std::size_t between = 0;
  for (std::size_t k = peak_at + 1; k < du1.size(); ++k) {
    if (std::abs(du1[k]) > 1e-6 && std::abs(du1[k]) < std::abs(du1[peak_at]) - 1e-6) ++between;
  }
  EXPECT_GE(between, 10U) << "no ramp-out on the plant's side";
}

// Exception 4 (server device failure) is transient: the comm guard holds, the run completes.
TEST_F(Refused, ADeviceFailureExceptionStaysTransientAndTheRunCompletes) {
  start({"--exception-requests", "3", "--faults-after", "300"});
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err().substr(0, 2000);
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 0) << err;
  EXPECT_NE(err.find("exception replies by code: 4 (server device failure) 3\n"), std::string::npos)
      << err;
  EXPECT_EQ(err.find("device refused"), std::string::npos) << err;
}

// Issue 28 item 1, second part: a lock-step gateway whose device answers every request with
// exception 4 (busy, transient: the comm guard) retries a few times a second, not as fast as
// the loopback answers; the log grows by as few rows. Stopped after 3 s by a double SIGTERM
// (the baseline cannot be confirmed while every request fails): exit 9.
TEST_F(Refused, ABusyDeviceIsRetriedAFewTimesASecondInLockstep) {
  start({"--exception-requests", "65535", "--faults-after", "300"});
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  std::this_thread::sleep_for(3s);
  gw->signal(SIGTERM);
  std::this_thread::sleep_for(300ms);
  gw->signal(SIGTERM);
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err().substr(0, 2000);
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 9) << err.substr(0, 2000);
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  std::size_t failing = 0;
  for (std::uint32_t f : log.flags) failing += (f & runlog::kCommLost) != 0 ? 1U : 0U;
  std::printf("[ measured ] %zu rows flagged comm_lost in about 3.3 s of a busy device\n", failing);
  EXPECT_GE(failing, 5U) << "the gateway did not retry";
  EXPECT_LE(failing, 30U) << "retries not paced (4 a second at most)";
  EXPECT_EQ(err.find("retries paced 0\n"), std::string::npos) << err.substr(0, 3000);
}

}  // namespace
}  // namespace excite::test
