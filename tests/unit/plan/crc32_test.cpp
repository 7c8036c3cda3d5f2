// SPDX-License-Identifier: MIT
#include "firmware/plan/crc32.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string_view>
#include <vector>

namespace excite::plan {
namespace {

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(Crc32, OfTheStandardCheckInputIsCBF43926) {
  EXPECT_EQ(crc32(bytes_of("123456789")), 0xCBF43926U);
}

TEST(Crc32, OfNothingIsZero) {
  EXPECT_EQ(crc32({}), 0U);
}

TEST(Crc32, OfAMillionAIsTheReferenceValue) {
  // Reference value from zlib's crc32 (the same CRC-32/IEEE) of 10^6 bytes 'a'.
  const std::vector<std::uint8_t> data(1'000'000, 'a');
  EXPECT_EQ(crc32(data), 0xDC25BFBCU);
}

TEST(Crc32, UpdatedPieceByPieceEqualsTheWholeAtOnce) {
  const std::string_view text = "the plan file of excite, checked end to end";
  std::uint32_t crc = 0;
  for (std::size_t i = 0; i < text.size(); i += 5)
    crc = crc32_update(crc, bytes_of(text.substr(i, 5)));
  EXPECT_EQ(crc, crc32(bytes_of(text)));
}

}  // namespace
}  // namespace excite::plan
