// SPDX-License-Identifier: MIT
// The loop over SocketCAN on vcan0 (label can-vm: toolchain/can-vm runs it in a VM; it
// skips elsewhere, naming why): the real excite-gateway streams a case-study plan to the
// real excite-plant --can through the pair `excite loop-config --transport can` wrote, in
// lock-step, and the run log is `excite simulate` of the same plan; the plant's watchdog
// brings its inputs back to the baseline after the gateway is SIGKILLed; can-utils, CAN
// tools we did not write, are the outside peer: cansend drives the plant (and its refusals
// of a short frame and of a setpoint beyond its limits), candump reads the gateway's
// setpoint frames, decoded as the default CAN frame map says (sim/server/README.md).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "can_loop_fixture.hpp"
#include "firmware/runlog/format.hpp"
#include "loop_facts.hpp"

namespace excite::test {
namespace {

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b,
                          std::size_t rows, std::size_t shift = 0) {
  double worst = 0.0;
  for (std::size_t k = shift; k < rows; ++k) worst = std::max(worst, std::abs(a[k] - b[k - shift]));
  return worst;
}

// GIVEN the case-study plan of alatiqi4x4 and the CAN pair from loop-config;
// WHEN the real gateway streams it over vcan0 to the real plant in lock-step;
// THEN its run log equals `excite simulate` (float32 frames aside), and so does the plant's.
TEST_F(CanLoop, CaseStudyPlanInLockstepOverVcanEqualsExciteSimulate) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  const std::string plant = "alatiqi4x4";
  const fs::path plan = design(plant, "prbsSimDir");
  start_can_loop(plant, "--noise-var 5e-4 --seed 7", {"--clock", "lockstep"});
  auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(300s);
  ASSERT_TRUE(rc.has_value()) << "the gateway did not finish";
  ASSERT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog plant_log = stop_plant_and_read_its_log();
  const std::string simulate = std::string(EXCITE_TOOL) + " simulate " + plan.string() +
                               " --plant " + plant + " --noise-var 5e-4 --seed 7 -o " +
                               path("sim.csv").string() + " > /dev/null";
  ASSERT_TRUE(shell(simulate)) << simulate;
  const runlog::RunLog sim = read_log_or_fail(path("sim.csv"));
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  const std::size_t n = sim.rows();
  ASSERT_GE(gwl.rows(), n);
  ASSERT_EQ(plant_log.rows(), gwl.rows()) << "one plant sample per gateway tick";
  for (std::size_t i = 0; i < sim.du.size(); ++i) {
    EXPECT_LE(max_abs_difference(gwl.du[i], sim.du[i], n), 0x1p-52 * max_abs(gwl.u[i]));
    EXPECT_LE(max_abs_difference(plant_log.du[i], gwl.du[i], gwl.rows()),
              kFloat32Epsilon * max_abs(plant_log.u[i]) * 2)
        << "input " << sim.input_names[i] << " as the plant received it";
  }
  const double tolerance = 2e-6;  // as over Modbus: gains ~10, inputs ~1, float32 frames
  for (std::size_t j = 0; j < sim.dy.size(); ++j) {
    EXPECT_LE(max_abs_difference(gwl.dy[j], sim.dy[j], n), tolerance)
        << "output " << sim.output_names[j];
    EXPECT_GT(max_abs_difference(gwl.dy[j], sim.dy[j], n, 1), 10 * tolerance)
        << "a one-sample shift must show";
  }
  EXPECT_NE(plant_->stderr_text().find("0 frames refused for their DLC"), std::string::npos)
      << plant_->stderr_text();
}

// GIVEN the gateway streaming every 5 ms to a plant with a 0.5 s heartbeat watchdog;
// WHEN the gateway is SIGKILLed mid-run;
// THEN the plant's readback frames (the setpoints it applies) are back at the baseline
// within the watchdog time + 0.5 s, not before its timeout, and one trip is counted.
TEST_F(CanLoop, GatewaySigkilledThePlantsWatchdogReturnsItsInputsToTheBaseline) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  const std::string plant = "woodberry2x2";
  const fs::path plan = design(plant, "prbsUnc");
  start_can_loop(plant, "--input-range 2 --period-s 0.005",
                 {"--clock", "lockstep", "--watchdog-s", "0.5"});
  real_time_gateway();
  BusObserver bus;
  ASSERT_TRUE(bus.ok());
  auto gw = start_gateway(plan, {"--start"});
  // Mid-run: the readbacks (0x380: u1_sp, u2_sp) have left the baseline (0 for woodberry).
  bool excited = false;
  for (auto until = Clock::now() + 20s; !excited && Clock::now() < until;) {
    const auto seen = bus.collect(50ms);
    if (const auto f = seen.find(0x380); f != seen.end()) {
      excited = float_at(f->second, 0) != 0.0F || float_at(f->second, 4) != 0.0F;
    }
  }
  ASSERT_TRUE(excited) << gw->err();
  ASSERT_FALSE(gw->wait(0ms).has_value()) << "the run ended too soon: " << gw->err();
  gw->signal(SIGKILL);
  const auto killed = Clock::now();
  ASSERT_EQ(gw->wait(10s).value_or(-1), 128 + SIGKILL);
  bool back = false;
  double after_s = 0.0;
  while (!back && Clock::now() - killed < 1s) {
    const auto seen = bus.collect(10ms);
    if (const auto f = seen.find(0x380); f != seen.end()) {
      back = float_at(f->second, 0) == 0.0F && float_at(f->second, 4) == 0.0F;
    }
    after_s = std::chrono::duration<double>(Clock::now() - killed).count();
  }
  EXPECT_TRUE(back) << "the plant's inputs are not back at baseline 1 s after the kill\n"
                    << plant_->stderr_text();
  EXPECT_GE(after_s, 0.45) << "the watchdog tripped before its timeout";
  std::printf("[ measured ] plant back at baseline %.3f s after SIGKILL (watchdog 0.5 s)\n",
              after_s);
  const auto held = bus.collect(200ms);  // held there: the plant repeats its frames
  ASSERT_TRUE(held.count(0x380));
  EXPECT_EQ(float_at(held.at(0x380), 0), 0.0F);
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0);
  EXPECT_NE(plant_->stderr_text().find("1 watchdog trips"), std::string::npos)
      << plant_->stderr_text();
}

// GIVEN a run over vcan0 (gateway every 5 ms, value frames stale after 100 ms, readbacks
// compared with the write 3 ticks back);
// WHEN the plant is SIGKILLed mid-run (its frames stop) and restarted 0.6 s later;
// THEN the gateway flags the stale frames as a comm loss, holds, resumes with the new plant
// and finishes (exit 0); the restarted plant never sees an input outside its limits and
// ends at the baseline.
TEST_F(CanLoop, PlantKilledMidRunFramesGoStaleAndTheRunResumesWhenItIsBack) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  const std::string plant = "woodberry2x2";
  const fs::path plan = design(plant, "prbsUnc");
  start_can_loop(plant, "--input-range 2 --period-s 0.005", {"--clock", "lockstep"});
  real_time_gateway();
  auto gw = start_gateway(plan, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples("plant.csv", 150)) << gw->err();
  plant_->stop(SIGKILL);
  std::this_thread::sleep_for(600ms);
  plant_ = std::make_unique<PlantRunner>(
      std::vector<std::string>{"--config", path("plant.toml").string(), "--can", kBus, "--log",
                               path("plant2.csv").string(), "--clock", "lockstep"},
      path("plant2.stderr"));
  plant_->wait_listening();
  ASSERT_EQ(plant_->first_line(), "listening can " + std::string(kBus));
  const auto rc = gw->wait(300s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  std::size_t lost = 0;
  for (std::uint32_t f : log.flags) lost += (f & runlog::kCommLost) != 0 ? 1U : 0U;
  EXPECT_GT(lost, 0U) << "the loss is not marked in the log";
  EXPECT_GT(can_count(gw->err(), "reads with a value frame stale or missing"), 0) << gw->err();
  const runlog::RunLog second = stop_plant_and_read_its_log("plant2.csv");
  ASSERT_GT(second.rows(), 0U);
  for (std::size_t i = 0; i < second.du.size(); ++i) {
    EXPECT_LE(max_abs(second.du[i]), 2.0 * (1 + 1e-6)) << second.input_names[i];
    EXPECT_EQ(second.du[i].back(), 0.0) << second.input_names[i] << " not back at baseline";
  }
}

// GIVEN the plant on vcan0 in lock-step; WHEN cansend (can-utils) writes setpoint frames
// and heartbeats; THEN the plant's readback frames carry what was sent, its log has one
// sample per heartbeat with those inputs, and a frame too short or with a setpoint beyond
// the input limits is refused (the readbacks keep the last good value) and counted, as is
// (and ignored) a frame of an identifier the map does not have.
TEST_F(CanLoop, CansendDrivesThePlantWhichRefusesShortFramesAndValuesBeyondItsLimits) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  if (!fs::exists("/usr/bin/cansend")) GTEST_SKIP() << "cansend not installed (can-utils)";
  start_can_loop("woodberry2x2", "--input-range 2", {"--clock", "lockstep"});
  BusObserver bus;
  ASSERT_TRUE(bus.ok());
  const auto cansend = [](const std::string& frame) {
    return shell(std::string("/usr/bin/cansend ") + kBus + " " + frame);
  };
  ASSERT_TRUE(cansend(float_frame(0x200, {0.5F, -1.25F})));
  // woodberry2x2 (2 inputs): u1, u2 in 0x200, the heartbeat in 0x201 (sim/server/README.md).
  ASSERT_TRUE(cansend("201#0100"));  // heartbeat 1: one sample with u = (0.5, -1.25)
  auto seen = bus.collect(300ms);
  ASSERT_TRUE(seen.count(0x380) && seen.count(0x3F0)) << plant_->stderr_text();
  EXPECT_EQ(float_at(seen.at(0x380), 0), 0.5F);
  EXPECT_EQ(float_at(seen.at(0x380), 4), -1.25F);
  EXPECT_EQ(seen.at(0x3F0).data[0], 1);  // the echo
  ASSERT_TRUE(cansend("123#0000803F"));  // an identifier the map does not have: ignored
  ASSERT_TRUE(cansend("200#0000"));      // DLC 2: two floats need 8 bytes
  ASSERT_TRUE(cansend(float_frame(0x200, {3.0F, 0.0F})));  // u1 = 3 beyond 0 ± 2
  ASSERT_TRUE(cansend("201#0200"));                        // heartbeat 2
  seen = bus.collect(300ms);
  ASSERT_TRUE(seen.count(0x380));
  EXPECT_EQ(float_at(seen.at(0x380), 0), 0.5F) << "the last good setpoint holds";
  EXPECT_EQ(seen.at(0x3F0).data[0], 2);
  const runlog::RunLog log = stop_plant_and_read_its_log();
  ASSERT_EQ(log.rows(), 2U) << "one sample per heartbeat change";
  EXPECT_EQ(log.u[0][0], 0.5);
  EXPECT_EQ(log.u[1][0], -1.25);
  EXPECT_EQ(log.u[0][1], 0.5);
  const std::string err = plant_->stderr_text();
  EXPECT_NE(err.find("frame 0x200 refused: DLC 2, expected at least 8"), std::string::npos) << err;
  EXPECT_NE(err.find("frame 0x200 refused: input u1 = 3 outside its limits"), std::string::npos)
      << err;
  EXPECT_NE(err.find("1 frames refused for their DLC, 1 frames refused for the input limits, 1 "
                     "frames of other identifiers"),
            std::string::npos)
      << err;
}

// GIVEN candump (can-utils) on vcan0 listening for identifiers 0x200..0x20F;
// WHEN the gateway streams woodberry2x2's plan to the plant in lock-step;
// THEN the setpoint frames decoded as the map says (float32 little-endian, u1 at byte 0,
// u2 at byte 4 of 0x200; the heartbeat uint16 in 0x201) are the gateway's logged setpoints,
// row for row, and the heartbeat counts up by one per row.
TEST_F(CanLoop, CandumpReadsTheGatewaysSetpointFramesAsTheMapSays) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  if (!fs::exists("/usr/bin/candump")) GTEST_SKIP() << "candump not installed (can-utils)";
  const std::string plant = "woodberry2x2";
  const fs::path plan = design(plant, "prbsUnc");
  start_can_loop(plant, "--input-range 2", {"--clock", "lockstep"});
  const fs::path dump = path("candump.log");
  constexpr int kRows = 200;  // two frames per row: 0x200 (u1, u2), 0x201 (heartbeat)
  PlantRunner candump("/bin/sh",
                      {"-c", "exec /usr/bin/candump -L -n " + std::to_string(2 * kRows) + " " +
                                 kBus + ",200:7F0 > " + dump.string()},
                      path("candump.err"));
  std::this_thread::sleep_for(300ms);  // candump has bound its socket
  auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
  ASSERT_EQ(gw->wait(300s).value_or(-1), 0) << gw->err();
  ASSERT_EQ(candump.wait_exit(10s).value_or(-1), 0) << "candump did not see its frames";
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(gwl.rows(), static_cast<std::size_t>(kRows));
  // "(1700000000.123456) vcan0 200#0000003F0000A0BF"
  std::ifstream in(dump);
  std::vector<std::vector<std::uint8_t>> u_frames;
  std::vector<unsigned> heartbeats;
  for (std::string stamp, iface, frame; in >> stamp >> iface >> frame;) {
    const auto hash = frame.find('#');
    ASSERT_NE(hash, std::string::npos) << frame;
    std::vector<std::uint8_t> data;
    for (std::size_t b = hash + 1; b + 1 < frame.size(); b += 2) {
      data.push_back(static_cast<std::uint8_t>(std::stoul(frame.substr(b, 2), nullptr, 16)));
    }
    const std::string id = frame.substr(0, hash);
    if (id == "200") {
      ASSERT_EQ(data.size(), 8U) << frame;
      u_frames.push_back(data);
    } else {
      ASSERT_EQ(id, "201") << frame;
      ASSERT_EQ(data.size(), 2U) << frame;
      heartbeats.push_back(data[0] | static_cast<unsigned>(data[1]) << 8);
    }
  }
  ASSERT_EQ(u_frames.size(), static_cast<std::size_t>(kRows));
  ASSERT_EQ(heartbeats.size(), static_cast<std::size_t>(kRows));
  for (std::size_t r = 0; r < u_frames.size(); ++r) {
    for (int i = 0; i < 2; ++i) {
      float u = 0.0F;
      std::memcpy(&u, u_frames[r].data() + 4 * i, 4);
      ASSERT_EQ(u, static_cast<float>(gwl.u[static_cast<std::size_t>(i)][r]))
          << "row " << r << " u" << i + 1;
    }
    if (r > 0) {
      ASSERT_EQ(heartbeats[r], (heartbeats[r - 1] + 1) & 0xFFFF) << "row " << r;
    }
  }
}

}  // namespace
}  // namespace excite::test
