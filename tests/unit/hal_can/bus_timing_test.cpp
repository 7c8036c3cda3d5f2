// SPDX-License-Identifier: MIT
// The bus-time arithmetic of hal/can/bus_timing.hpp: the worst-case frame lengths of the
// literature, the figures hal/can/README.md quotes for a 4x4 loop, and the refusal of a
// configuration whose frames cannot fit the tick.
#include <gtest/gtest.h>

#include <string>

#include "hal/can/bus_timing.hpp"

using namespace excite::hal::can;

namespace {

// The default CAN frame map of a 4x4 plant (sim/server/README.md): 0x200, 0x201 two float32
// setpoints each, 0x202 the uint16 heartbeat; the peer answers with 0x300, 0x301 (outputs),
// 0x380, 0x381 (readbacks), 0x3F0 (echo, uint16).
CanPlan four_by_four() {
  CanFrameMap map;
  for (std::uint32_t i = 0; i < 4; ++i) {
    map.setpoints.push_back(
        {"u" + std::to_string(i), 0x200 + i / 2, false, 4 * (i % 2), "float32", "little", 1, 0});
    map.values.push_back(
        {"y" + std::to_string(i), 0x300 + i / 2, false, 4 * (i % 2), "float32", "little", 1, 0});
  }
  for (std::uint32_t i = 0; i < 4; ++i) {
    map.values.push_back(
        {"r" + std::to_string(i), 0x380 + i / 2, false, 4 * (i % 2), "float32", "little", 1, 0});
  }
  map.heartbeat = CanSignal{"hb", 0x202, false, 0, "uint16", "little", 1, 0};
  map.values.push_back({"echo", 0x3F0, false, 0, "uint16", "little", 1, 0});
  CanPlan plan;
  EXPECT_TRUE(compile_frame_map(map, plan).ok());
  return plan;
}

}  // namespace

TEST(BusTiming, WorstCaseFrameLengthsAreThoseOfTheLiterature) {
  EXPECT_EQ(worst_case_frame_bits(8, false), 135U);  // Davis et al. 2007: 135 bits
  EXPECT_EQ(worst_case_frame_bits(8, true), 160U);
  EXPECT_EQ(worst_case_frame_bits(0, false), 55U);
  EXPECT_EQ(worst_case_frame_bits(2, false), 75U);
}

TEST(BusTiming, AFourByFourLoopNeedsEightFramesOf960BitsPerTick) {
  const CanPlan plan = four_by_four();
  const TickLoad at125k_1s = tick_load(plan, 125000, 1.0);
  EXPECT_EQ(at125k_1s.frames, 8U);                  // 3 sent, 5 answered
  EXPECT_EQ(at125k_1s.bits, 6U * 135U + 2U * 75U);  // six of 8 bytes, two of 2 bytes
  EXPECT_DOUBLE_EQ(at125k_1s.seconds, 0.00768);
  EXPECT_DOUBLE_EQ(at125k_1s.load, 0.00768);
  EXPECT_DOUBLE_EQ(tick_load(plan, 125000, 0.1).load, 0.0768);
  EXPECT_DOUBLE_EQ(tick_load(plan, 500000, 0.1).load, 0.0192);
}

TEST(BusTiming, FramesThatCannotFitTheTickAreRefusedNamingTheLoad) {
  const CanPlan plan = four_by_four();
  EXPECT_TRUE(check_tick_fits(plan, 125000, 0.0077).ok());  // 7.68 ms of 7.7
  const auto v = check_tick_fits(plan, 125000, 0.005);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "can.bitrate");
  EXPECT_EQ(v.value, "125000");
  EXPECT_NE(v.expected.find("8 frames, 960 bits at worst per tick need 7.68 ms, the tick is 5 ms"),
            std::string::npos)
      << v.message();
  EXPECT_TRUE(check_tick_fits(plan, 0, 0.001).ok()) << "a virtual bus is not checked";
}
