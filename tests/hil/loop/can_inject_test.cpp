// SPDX-License-Identifier: MIT
// Issue 20: wrong DLC and wrong identifiers on the bus, in the VM (label can-vm). While the real
// gateway streams a case-study plan to the real plant over vcan0 in lock-step, a third node
// (cansend, can-utils) sends frames with the plant's answer identifiers but too short a DLC,
// frames with the gateway's own setpoint identifier, and frames of an identifier nobody maps.
// Both ends refuse and count them, and the run is still `excite simulate` of the plan.
#include <cmath>
#include <cstdio>
#include <string>

#include "can_loop_fixture.hpp"

namespace excite::test {
namespace {

constexpr int kRounds = 10;

double worst_difference(const std::vector<double>& a, const std::vector<double>& b,
                        std::size_t rows) {
  double worst = 0.0;
  for (std::size_t k = 0; k < rows; ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

class CanInject : public CanLoop {};

// GIVEN alatiqi4x4's prbsSimDir plan (4080 rows) streamed in lock-step over vcan0: the gateway
// sends 0x200, 0x201 (setpoints) and 0x202 (heartbeat); the plant answers 0x300, 0x301
// (outputs), 0x380, 0x381 (readbacks), 0x3F0 (echo, 2 bytes);
// WHEN, mid-run, cansend sends 10 times each: 300#0000 (DLC 2, 8 expected), 3F0#01 (DLC 1, 2
// expected), 200#00 (the gateway's identifier, DLC 1) and 123#DEADBEEF (mapped by nobody);
// THEN the gateway refuses the 20 short value frames and counts them, counts the 10 frames of
// its own identifier sent by another node (0x123 never reaches it: its receive filter), the
// plant refuses the 10 short 0x200 frames and counts the 30 frames of identifiers it does not
// take; the run ends with exit 0 and its log equals `excite simulate` (du exactly, dy within
// 2e-6), one plant sample per row.
TEST_F(CanInject, ShortFramesAndForeignIdentifiersAreRefusedCountedAndTheRunEndsRight) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  ASSERT_EQ(access("/usr/bin/cansend", X_OK), 0) << "cansend not found (can-utils)";
  const std::string plant = "alatiqi4x4";
  const fs::path plan = design(plant, "prbsSimDir");
  start_can_loop(plant, "--noise-var 5e-4 --seed 7", {"--clock", "lockstep"});
  auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
  ASSERT_TRUE(wait_for_plant_samples("plant.csv", 100)) << gw->err();
  const std::string send = std::string("/usr/bin/cansend ") + kBus + " ";
  const std::string script = "for i in $(seq " + std::to_string(kRounds) + "); do " + send +
                             "300#0000 && " + send + "3F0#01 && " + send + "200#00 && " + send +
                             "123#DEADBEEF || exit 1; done";
  ASSERT_TRUE(shell(script)) << script;
  ASSERT_FALSE(gw->wait(0ms).has_value()) << "the run ended before the last injected frame";

  const auto rc = gw->wait(300s);
  ASSERT_TRUE(rc.has_value()) << "the gateway did not finish";
  const std::string err = gw->err();
  ASSERT_EQ(*rc, 0) << err;
  EXPECT_NE(err.find("excite-gateway: can vcan0: value frames refused for their DLC 20 (first "
                     "0x300 DLC 2), frames of the gateway's own identifiers from another node 10 "
                     "(first 0x200), sends refused 0"),
            std::string::npos)
      << err;

  const runlog::RunLog plant_log = stop_plant_and_read_its_log();
  const std::string plant_err = plant_->stderr_text();
  EXPECT_NE(plant_err.find("frame 0x200 refused: DLC 1, expected at least 8"), std::string::npos)
      << plant_err;
  EXPECT_NE(plant_err.find("10 frames refused for their DLC, 0 frames refused for the input "
                           "limits, 30 frames of other identifiers"),
            std::string::npos)
      << plant_err;

  const std::string simulate = std::string(EXCITE_TOOL) + " simulate " + plan.string() +
                               " --plant " + plant + " --noise-var 5e-4 --seed 7 -o " +
                               path("sim.csv").string() + " > /dev/null";
  ASSERT_TRUE(shell(simulate)) << simulate;
  const runlog::RunLog sim = read_log_or_fail(path("sim.csv"));
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  const std::size_t n = sim.rows();
  ASSERT_GE(gwl.rows(), n);
  EXPECT_EQ(plant_log.rows(), gwl.rows()) << "one plant sample per gateway tick";
  for (std::size_t i = 0; i < sim.du.size(); ++i) {
    EXPECT_EQ(worst_difference(gwl.du[i], sim.du[i], n), 0.0) << sim.input_names[i];
  }
  for (std::size_t j = 0; j < sim.dy.size(); ++j) {
    EXPECT_LE(worst_difference(gwl.dy[j], sim.dy[j], n), 2e-6) << sim.output_names[j];
  }
  for (std::uint32_t f : gwl.flags) ASSERT_EQ(f, 0U) << "a row flagged: the run was disturbed";
}

}  // namespace
}  // namespace excite::test
