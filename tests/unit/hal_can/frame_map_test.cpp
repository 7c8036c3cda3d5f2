// SPDX-License-Identifier: MIT
// CAN frame packing and frame-map validation: pure, runs on any kernel.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "hal/can/frame_map.hpp"

using namespace excite::hal;
using namespace excite::hal::can;

namespace {

CanSignal signal(std::uint32_t id, std::uint32_t byte, const char* type,
                 const char* order = "little", double scale = 1.0, double offset = 0.0) {
  return CanSignal{"s", id, false, byte, type, order, scale, offset};
}

// Two setpoints in 0x200 (int16 little at 0, uint16 big at 2, 0.1 units/count),
// a float32 setpoint in extended 0x18FF0001, heartbeat uint8 at 0x200 byte 7;
// two values in 0x300.
CanFrameMap tick_map() {
  CanFrameMap map;
  map.setpoints = {signal(0x200, 0, "int16", "little", 0.1),
                   signal(0x200, 2, "uint16", "big", 0.1, -100.0),
                   CanSignal{"flow", 0x18FF0001, true, 0, "float32", "little", 1.0, 0.0}};
  map.heartbeat = signal(0x200, 7, "uint8");
  map.values = {signal(0x300, 0, "int16", "little", 0.01), signal(0x300, 4, "uint32", "big")};
  return map;
}

}  // namespace

TEST(CanFrameMap, GroupsSignalsIntoOneFramePerIdentifier) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  ASSERT_EQ(plan.tx.size(), 2U);
  EXPECT_EQ(plan.tx[0].can_id, 0x200U);
  EXPECT_EQ(plan.tx[0].can_dlc, 8);  // heartbeat in byte 7
  EXPECT_EQ(plan.tx[1].can_id, 0x18FF0001U | CAN_EFF_FLAG);
  EXPECT_EQ(plan.tx[1].can_dlc, 4);
  ASSERT_EQ(plan.rx.size(), 1U);
  EXPECT_EQ(plan.rx[0].dlc, 8);
}

TEST(CanFrameMap, PacksScaledIntegersInTheirByteOrderAndTheHeartbeat) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  std::vector<can_frame> frames(plan.tx.size());
  std::uint64_t clamped = 0;
  const std::array<double, 3> setpoints{-12.3, 20.0, 123456.0};
  ASSERT_EQ(pack_setpoints(plan, setpoints, 0x1A5, frames, clamped), StatusCode::ok);
  // -12.3 / 0.1 = -123 = 0xFF85, little-endian
  EXPECT_EQ(frames[0].data[0], 0x85);
  EXPECT_EQ(frames[0].data[1], 0xFF);
  // (20 - -100) / 0.1 = 1200 = 0x04B0, big-endian
  EXPECT_EQ(frames[0].data[2], 0x04);
  EXPECT_EQ(frames[0].data[3], 0xB0);
  EXPECT_EQ(frames[0].data[7], 0xA5);  // heartbeat, low byte of the counter
  // 123456.0f = 0x47F12000, little-endian
  EXPECT_EQ(frames[1].data[0], 0x00);
  EXPECT_EQ(frames[1].data[1], 0x20);
  EXPECT_EQ(frames[1].data[2], 0xF1);
  EXPECT_EQ(frames[1].data[3], 0x47);
  EXPECT_EQ(clamped, 0U);
}

TEST(CanFrameMap, ClampsSetpointsToTheRawTypeAndCountsThem) {
  CanPlan plan;
  CanFrameMap map;
  map.setpoints = {signal(0x10, 0, "uint8"), signal(0x10, 1, "int8")};
  ASSERT_TRUE(compile_frame_map(map, plan).ok());
  std::vector<can_frame> frames(1);
  std::uint64_t clamped = 0;
  const std::array<double, 2> setpoints{300.0, -200.0};
  ASSERT_EQ(pack_setpoints(plan, setpoints, 0, frames, clamped), StatusCode::ok);
  EXPECT_EQ(frames[0].data[0], 255);
  EXPECT_EQ(frames[0].data[1], 0x80);
  EXPECT_EQ(clamped, 2U);
}

TEST(CanFrameMap, RejectsNonFiniteSetpoints) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  std::vector<can_frame> frames(plan.tx.size());
  std::uint64_t clamped = 0;
  const std::array<double, 3> setpoints{0.0, std::nan(""), 0.0};
  EXPECT_EQ(pack_setpoints(plan, setpoints, 0, frames, clamped), StatusCode::bad_argument);
}

TEST(CanFrameMap, UnpacksValuesFromAMappedFrame) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  can_frame frame{};
  frame.can_id = 0x300;
  frame.can_dlc = 8;
  frame.data[0] = 0x30;  // 0xFF30 = -208 → -2.08
  frame.data[1] = 0xFF;
  frame.data[4] = 0x00;  // 0x0001E240 = 123456, big-endian
  frame.data[5] = 0x01;
  frame.data[6] = 0xE2;
  frame.data[7] = 0x40;
  const auto rx = find_rx(plan, frame);
  ASSERT_TRUE(rx.has_value());
  std::array<double, 2> values{};
  ASSERT_TRUE(unpack_values(plan, *rx, frame, values));
  EXPECT_DOUBLE_EQ(values[0], -2.08);
  EXPECT_DOUBLE_EQ(values[1], 123456.0);
}

TEST(CanFrameMap, RoundTripsEveryTypeThroughAFrame) {
  for (const char* type : {"int8", "uint8", "int16", "uint16", "int32", "uint32", "float32"}) {
    for (const char* order : {"little", "big"}) {
      CanFrameMap map;
      map.setpoints = {signal(0x100, 1, type, order, 0.5, 3.0)};
      map.values = {signal(0x101, 1, type, order, 0.5, 3.0)};
      CanPlan plan;
      ASSERT_TRUE(compile_frame_map(map, plan).ok()) << type;
      std::vector<can_frame> frames(1);
      std::uint64_t clamped = 0;
      const std::array<double, 1> setpoint{45.5};  // raw 85
      ASSERT_EQ(pack_setpoints(plan, setpoint, 0, frames, clamped), StatusCode::ok);
      frames[0].can_id = 0x101;  // the peer echoes it as a value frame
      std::array<double, 1> value{};
      ASSERT_TRUE(unpack_values(plan, 0, frames[0], value));
      EXPECT_DOUBLE_EQ(value[0], 45.5) << type << " " << order;
    }
  }
}

TEST(CanFrameMap, AShortFrameLeavesValuesUntouched) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  can_frame frame{};
  frame.can_id = 0x300;
  frame.can_dlc = 4;  // the uint32 at 4..7 is missing
  std::array<double, 2> values{7.0, 7.0};
  EXPECT_FALSE(unpack_values(plan, 0, frame, values));
  EXPECT_EQ(values, (std::array<double, 2>{7.0, 7.0}));
}

TEST(CanFrameMap, IgnoresUnmappedErrorAndRemoteFrames) {
  CanPlan plan;
  ASSERT_TRUE(compile_frame_map(tick_map(), plan).ok());
  can_frame frame{};
  frame.can_id = 0x301;
  EXPECT_FALSE(find_rx(plan, frame).has_value());
  frame.can_id = 0x300 | CAN_RTR_FLAG;
  EXPECT_FALSE(find_rx(plan, frame).has_value());
  frame.can_id = 0x300 | CAN_EFF_FLAG;  // same number, extended: another identifier
  EXPECT_FALSE(find_rx(plan, frame).has_value());
}

TEST(CanFrameMap, RejectsOverlappingBytesNamingTheOtherSignal) {
  CanFrameMap map;
  map.setpoints = {signal(0x200, 0, "int32"), signal(0x200, 3, "int16")};
  CanPlan plan;
  const auto v = compile_frame_map(map, plan);
  EXPECT_EQ(v.message(),
            "setpoints[1].byte_offset = 3, expected no overlap with setpoints[0] in frame 0x200");
  EXPECT_TRUE(plan.tx.empty());
}

TEST(CanFrameMap, RejectsASignalPastTheEightBytePayload) {
  CanFrameMap map;
  map.values = {signal(0x300, 6, "float32")};
  CanPlan plan;
  EXPECT_EQ(compile_frame_map(map, plan).message(),
            "values[0].byte_offset = 6, expected byte_offset + 4 byte(s) of float32 <= 8 (classic "
            "CAN payload)");
}

TEST(CanFrameMap, RejectsIdentifiersBeyondTheirFormat) {
  CanFrameMap map;
  map.values = {signal(0x800, 0, "int16")};
  CanPlan plan;
  auto v = compile_frame_map(map, plan);
  EXPECT_EQ(v.field, "values[0].id");
  EXPECT_EQ(v.value, "0x800");
  map.values[0].extended = true;
  EXPECT_TRUE(compile_frame_map(map, plan).ok());
  map.values[0].id = 0x20000000;
  EXPECT_EQ(compile_frame_map(map, plan).field, "values[0].id");
}

TEST(CanFrameMap, RejectsAnIdentifierUsedBothWays) {
  CanFrameMap map;
  map.setpoints = {signal(0x200, 0, "int16")};
  map.values = {signal(0x200, 2, "int16")};
  CanPlan plan;
  EXPECT_EQ(compile_frame_map(map, plan).field, "values[0].id");
}

TEST(CanFrameMap, RejectsUnknownTypesByteOrdersZeroScaleAndNonCounterHeartbeat) {
  CanPlan plan;
  CanFrameMap map;
  map.values = {signal(0x300, 0, "int24")};
  EXPECT_EQ(compile_frame_map(map, plan).field, "values[0].type");
  map.values = {signal(0x300, 0, "int16", "middle")};
  EXPECT_EQ(compile_frame_map(map, plan).field, "values[0].byte_order");
  map.values = {signal(0x300, 0, "int16", "little", 0.0)};
  EXPECT_EQ(compile_frame_map(map, plan).field, "values[0].scale");
  map.values = {};
  map.heartbeat = signal(0x200, 0, "float32");
  EXPECT_EQ(compile_frame_map(map, plan).field, "heartbeat.type");
}
