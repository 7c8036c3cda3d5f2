// SPDX-License-Identifier: MIT
// Register map compilation: chunking at the protocol limits, overlaps, address space,
// and the int16/uint16 scaling contract.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "hal/modbus/register_map.hpp"

using namespace excite::hal::modbus;

namespace {

RegisterEntry float_at(std::uint32_t address, int function_code = 16) {
  RegisterEntry entry;
  entry.address = address;
  entry.function_code = function_code;
  return entry;
}

RegisterEntry uint16_at(std::uint32_t address, int function_code = 16) {
  RegisterEntry entry = float_at(address, function_code);
  entry.type = "uint16";
  entry.eng_min = 0.0;
  entry.eng_max = 100.0;
  return entry;
}

// n contiguous uint16 entries from `first`.
std::vector<RegisterEntry> uint16_run(std::uint32_t first, std::uint32_t n, int function_code) {
  std::vector<RegisterEntry> run;
  for (std::uint32_t i = 0; i < n; ++i) {
    run.push_back(uint16_at(first + i, function_code));
  }
  return run;
}

}  // namespace

TEST(RegisterMap, ContiguousSetpointsAndHeartbeatShareOneRequest) {
  RegisterMap map;
  for (std::uint32_t i = 0; i < 4; ++i) {
    map.setpoints.push_back(float_at(100 + 2 * i));
  }
  map.heartbeat_address = 108;
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.writes.size(), 1U);
  EXPECT_EQ(plan.writes[0].address, 100);
  EXPECT_EQ(plan.writes[0].count, 9);
  EXPECT_EQ(plan.heartbeat_offset, 8U);
  EXPECT_EQ(plan.setpoints[3].offset, 6U);
}

TEST(RegisterMap, AGapStartsANewRequestSoItIsNeverWritten) {
  RegisterMap map;
  map.setpoints = {float_at(0), float_at(10)};
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.writes.size(), 2U);
  EXPECT_EQ(plan.writes[1].address, 10);
  EXPECT_EQ(plan.writes[1].offset, 2U);
}

TEST(RegisterMap, WritesSplitAt123Registers) {
  RegisterMap map;
  map.setpoints = uint16_run(0, 246, 16);
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  EXPECT_EQ(plan.writes.size(), 2U);
  map.setpoints = uint16_run(0, 247, 16);
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.writes.size(), 3U);
  EXPECT_EQ(plan.writes[0].count, 123);
  EXPECT_EQ(plan.writes[2].count, 1);
}

TEST(RegisterMap, ReadsSplitAt125Registers) {
  RegisterMap map;
  map.values = uint16_run(0, 250, 4);
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  EXPECT_EQ(plan.reads.size(), 2U);
  map.values = uint16_run(0, 251, 4);
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.reads.size(), 3U);
  EXPECT_EQ(plan.reads[0].count, 125);
}

TEST(RegisterMap, AFloatIsNeverSplitAcrossTwoRequests) {
  RegisterMap map;
  for (std::uint32_t i = 0; i < 150; ++i) {  // 300 registers
    map.setpoints.push_back(float_at(2 * i));
  }
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.writes.size(), 3U);
  EXPECT_EQ(plan.writes[0].count, 122);  // 61 floats; the 62nd would need register 123 and 124
  EXPECT_EQ(plan.writes[2].count, 56);
}

TEST(RegisterMap, HoldingAndInputRegistersAreSeparateTables) {
  RegisterMap map;
  map.values = {float_at(0, 3), float_at(0, 4), float_at(2, 3)};
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  ASSERT_EQ(plan.reads.size(), 2U);
  EXPECT_EQ(plan.reads[0].function_code, 3);
  EXPECT_EQ(plan.reads[0].count, 4);
  EXPECT_EQ(plan.reads[1].function_code, 4);
  EXPECT_EQ(plan.values[1].offset, 4U);
}

TEST(RegisterMap, ASmallerConfiguredChunkIsHonoured) {
  RegisterMap map;
  map.values = uint16_run(0, 100, 3);
  map.read_chunk = 40;
  RegisterPlan plan;
  ASSERT_TRUE(compile_register_map(map, plan).ok());
  EXPECT_EQ(plan.reads.size(), 3U);
}

TEST(RegisterMap, RejectsOverlappingValuesNamingBoth) {
  RegisterMap map;
  map.setpoints = {float_at(10), float_at(11)};
  RegisterPlan plan;
  const auto v = compile_register_map(map, plan);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "setpoints[1].address");
  EXPECT_EQ(v.value, "11");
  EXPECT_NE(v.expected.find("setpoints[0]"), std::string::npos) << v.message();
  EXPECT_NE(v.expected.find("10..11"), std::string::npos) << v.message();
  EXPECT_TRUE(plan.writes.empty());
}

TEST(RegisterMap, RejectsTheHeartbeatOnASetpoint) {
  RegisterMap map;
  map.setpoints = {float_at(10)};
  map.heartbeat_address = 11;
  RegisterPlan plan;
  const auto v = compile_register_map(map, plan);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "heartbeat_address");
}

TEST(RegisterMap, RejectsAFloatPastTheEndOfTheAddressSpace) {
  RegisterMap map;
  map.values = {float_at(65535, 3)};
  RegisterPlan plan;
  const auto v = compile_register_map(map, plan);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.message(), "values[0].address = 65535, expected address + 2 register(s) <= 65536");
  map.values = {uint16_at(65535, 3)};
  EXPECT_TRUE(compile_register_map(map, plan).ok());
}

TEST(RegisterMap, RejectsChunkLimitsBeyondTheProtocol) {
  RegisterMap map;
  map.write_chunk = 124;
  RegisterPlan plan;
  auto v = compile_register_map(map, plan);
  EXPECT_EQ(v.field, "write_chunk");
  EXPECT_EQ(v.value, "124");
  map.write_chunk = 123;
  map.read_chunk = 126;
  v = compile_register_map(map, plan);
  EXPECT_EQ(v.field, "read_chunk");
}

TEST(RegisterMap, RejectsAnUnknownWordOrder) {
  RegisterMap map;
  map.values = {float_at(0, 4)};
  map.values[0].word_order = "BACD";
  RegisterPlan plan;
  const auto v = compile_register_map(map, plan);
  EXPECT_EQ(v.message(), "values[0].word_order = \"BACD\", expected ABCD, CDAB, BADC or DCBA");
}

TEST(RegisterMap, RejectsWrongFunctionCodes) {
  RegisterMap map;
  map.setpoints = {float_at(0, 6)};
  RegisterPlan plan;
  EXPECT_EQ(compile_register_map(map, plan).field, "setpoints[0].function_code");
  map.setpoints = {};
  map.values = {float_at(0, 16)};
  const auto v = compile_register_map(map, plan);
  EXPECT_EQ(v.field, "values[0].function_code");
  EXPECT_EQ(v.value, "16");
}

TEST(RegisterMap, RejectsAnUnknownType) {
  RegisterMap map;
  map.values = {float_at(0, 3)};
  map.values[0].type = "float64";
  RegisterPlan plan;
  EXPECT_EQ(compile_register_map(map, plan).message(),
            "values[0].type = \"float64\", expected float32, int16 or uint16");
}

TEST(RegisterMap, RejectsAnEmptyEngineeringRangeAndRawRangesOutsideTheType) {
  RegisterMap map;
  map.setpoints = {uint16_at(0)};
  map.setpoints[0].eng_max = 0.0;
  RegisterPlan plan;
  EXPECT_EQ(compile_register_map(map, plan).field, "setpoints[0].eng_max");
  map.setpoints = {uint16_at(0)};
  map.setpoints[0].raw_min = -1;
  EXPECT_EQ(compile_register_map(map, plan).field, "setpoints[0].raw_min");
  map.setpoints[0].type = "int16";
  map.setpoints[0].raw_max = 40000;
  const auto v = compile_register_map(map, plan);
  EXPECT_EQ(v.field, "setpoints[0].raw_max");
  EXPECT_NE(v.expected.find("-32768..32767"), std::string::npos) << v.message();
}

// ---- scaling contract ----

namespace {
Codec scaled(RegisterType type, double eng_min, double eng_max, double raw_min, double raw_max) {
  Codec codec;
  codec.type = type;
  codec.eng_min = eng_min;
  codec.eng_max = eng_max;
  codec.raw_min = raw_min;
  codec.raw_max = raw_max;
  return codec;
}
}  // namespace

TEST(Scaling, Uint16MapsTheEngineeringRangeOntoTheRawRange) {
  const Codec codec =
      scaled(RegisterType::uint16, 0.0, 100.0, 0.0, 27648.0);  // Siemens analog span
  bool clamped = true;
  EXPECT_EQ(to_raw(codec, 0.0, clamped), 0);
  EXPECT_FALSE(clamped);
  EXPECT_EQ(to_raw(codec, 50.0, clamped), 13824);
  EXPECT_EQ(to_raw(codec, 100.0, clamped), 27648);
  EXPECT_DOUBLE_EQ(from_raw(codec, 13824), 50.0);
}

TEST(Scaling, SetpointsOutsideTheEngineeringRangeAreClampedAndFlagged) {
  const Codec codec = scaled(RegisterType::uint16, 0.0, 100.0, 0.0, 65535.0);
  bool clamped = false;
  EXPECT_EQ(to_raw(codec, 130.0, clamped), 65535);
  EXPECT_TRUE(clamped);
  EXPECT_EQ(to_raw(codec, -5.0, clamped), 0);
  EXPECT_TRUE(clamped);
}

TEST(Scaling, Int16TravelsAsTwosComplement) {
  const Codec codec = scaled(RegisterType::int16, -10.0, 10.0, -32768.0, 32767.0);
  bool clamped = false;
  EXPECT_EQ(to_raw(codec, -10.0, clamped), 0x8000);
  EXPECT_EQ(to_raw(codec, 10.0, clamped), 0x7FFF);
  EXPECT_DOUBLE_EQ(from_raw(codec, 0x8000), -10.0);
  EXPECT_NEAR(from_raw(codec, to_raw(codec, 1.25, clamped)), 1.25, 20.0 / 65535.0);
}

TEST(Scaling, ReadValuesOutsideTheRawRangeAreNotClamped) {
  const Codec codec = scaled(RegisterType::uint16, 0.0, 100.0, 0.0, 27648.0);
  EXPECT_GT(from_raw(codec, 32767), 100.0);  // Siemens overflow code stays visible
}

TEST(Scaling, RoundsToTheNearestRawStep) {
  const Codec codec = scaled(RegisterType::uint16, 0.0, 1.0, 0.0, 10.0);
  bool clamped = false;
  EXPECT_EQ(to_raw(codec, 0.449, clamped), 4);
  EXPECT_EQ(to_raw(codec, 0.451, clamped), 5);
}
