// SPDX-License-Identifier: MIT
// Float32 word orders against the oracle 123456.0f = 0x47F12000 (bytes A=47 B=F1 C=20 D=00).
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <limits>

#include "hal/modbus/word_order.hpp"

using excite::hal::modbus::decode_float32;
using excite::hal::modbus::encode_float32;
using excite::hal::modbus::parse_word_order;
using excite::hal::modbus::WordOrder;

namespace {

struct Oracle {
  WordOrder order;
  std::array<std::uint16_t, 2> registers;
};

constexpr float oracle_value = 123456.0F;
constexpr std::array<Oracle, 4> oracles{{
    {WordOrder::abcd, {0x47F1, 0x2000}},
    {WordOrder::cdab, {0x2000, 0x47F1}},
    {WordOrder::badc, {0xF147, 0x0020}},
    {WordOrder::dcba, {0x0020, 0xF147}},
}};

}  // namespace

TEST(WordOrder, OracleBitPatternIs47F12000) {
  EXPECT_EQ(std::bit_cast<std::uint32_t>(oracle_value), 0x47F12000U);
}

TEST(WordOrder, EncodesTheOracleInAllFourOrders) {
  for (const Oracle& oracle : oracles) {
    std::array<std::uint16_t, 2> registers{};
    encode_float32(oracle_value, oracle.order, registers.data());
    EXPECT_EQ(registers, oracle.registers) << to_string(oracle.order);
  }
}

TEST(WordOrder, DecodesTheOracleInAllFourOrders) {
  for (const Oracle& oracle : oracles) {
    EXPECT_EQ(decode_float32(oracle.registers.data(), oracle.order), oracle_value)
        << to_string(oracle.order);
  }
}

TEST(WordOrder, RoundTripsAwkwardValuesBitExactly) {
  const std::array<float, 7> samples{-0.0F,
                                     1.0F / 3.0F,
                                     -273.15F,
                                     std::numeric_limits<float>::denorm_min(),
                                     std::numeric_limits<float>::max(),
                                     std::numeric_limits<float>::infinity(),
                                     -1.5e-20F};
  for (WordOrder order : {WordOrder::abcd, WordOrder::cdab, WordOrder::badc, WordOrder::dcba}) {
    for (float sample : samples) {
      std::array<std::uint16_t, 2> registers{};
      encode_float32(sample, order, registers.data());
      EXPECT_EQ(std::bit_cast<std::uint32_t>(decode_float32(registers.data(), order)),
                std::bit_cast<std::uint32_t>(sample))
          << to_string(order) << " " << sample;
    }
  }
}

TEST(WordOrder, DecodingInTheWrongOrderGivesAnotherNumber) {
  std::array<std::uint16_t, 2> registers{};
  encode_float32(oracle_value, WordOrder::abcd, registers.data());
  EXPECT_NE(decode_float32(registers.data(), WordOrder::cdab), oracle_value);
}

TEST(WordOrder, ParsesTheFourNamesCaseInsensitively) {
  EXPECT_EQ(parse_word_order("ABCD"), WordOrder::abcd);
  EXPECT_EQ(parse_word_order("cdab"), WordOrder::cdab);
  EXPECT_EQ(parse_word_order("BaDc"), WordOrder::badc);
  EXPECT_EQ(parse_word_order("DCBA"), WordOrder::dcba);
}

TEST(WordOrder, RejectsUnknownNames) {
  EXPECT_FALSE(parse_word_order("ACBD").has_value());
  EXPECT_FALSE(parse_word_order("").has_value());
  EXPECT_FALSE(parse_word_order("ABCDE").has_value());
}
