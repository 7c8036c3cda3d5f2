// SPDX-License-Identifier: MIT
#include "hal/modbus/word_order.hpp"

#include <bit>
#include <cctype>

namespace excite::hal::modbus {

namespace {

constexpr std::uint16_t swap_bytes(std::uint16_t word) noexcept {
  return static_cast<std::uint16_t>((word >> 8U) | (word << 8U));
}

bool equals_ignoring_case(std::string_view a, std::string_view b) noexcept {
  if (a.size() != b.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::toupper(static_cast<unsigned char>(a[i])) !=
        std::toupper(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::optional<WordOrder> parse_word_order(std::string_view text) noexcept {
  for (WordOrder order : {WordOrder::abcd, WordOrder::cdab, WordOrder::badc, WordOrder::dcba}) {
    if (equals_ignoring_case(text, to_string(order))) {
      return order;
    }
  }
  return std::nullopt;
}

const char* to_string(WordOrder order) noexcept {
  switch (order) {
    case WordOrder::abcd:
      return "ABCD";
    case WordOrder::cdab:
      return "CDAB";
    case WordOrder::badc:
      return "BADC";
    case WordOrder::dcba:
      return "DCBA";
  }
  return "?";
}

void encode_float32(float value, WordOrder order, std::uint16_t* registers) noexcept {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  const auto ab = static_cast<std::uint16_t>(bits >> 16U);
  const auto cd = static_cast<std::uint16_t>(bits & 0xFFFFU);
  switch (order) {
    case WordOrder::abcd:
      registers[0] = ab;
      registers[1] = cd;
      break;
    case WordOrder::cdab:
      registers[0] = cd;
      registers[1] = ab;
      break;
    case WordOrder::badc:
      registers[0] = swap_bytes(ab);
      registers[1] = swap_bytes(cd);
      break;
    case WordOrder::dcba:
      registers[0] = swap_bytes(cd);
      registers[1] = swap_bytes(ab);
      break;
  }
}

float decode_float32(const std::uint16_t* registers, WordOrder order) noexcept {
  std::uint16_t ab = 0;
  std::uint16_t cd = 0;
  switch (order) {
    case WordOrder::abcd:
      ab = registers[0];
      cd = registers[1];
      break;
    case WordOrder::cdab:
      cd = registers[0];
      ab = registers[1];
      break;
    case WordOrder::badc:
      ab = swap_bytes(registers[0]);
      cd = swap_bytes(registers[1]);
      break;
    case WordOrder::dcba:
      cd = swap_bytes(registers[0]);
      ab = swap_bytes(registers[1]);
      break;
  }
  return std::bit_cast<float>((static_cast<std::uint32_t>(ab) << 16U) | cd);
}

}  // namespace excite::hal::modbus
