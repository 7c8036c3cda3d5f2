// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace excite::hal::modbus {

// How a float32's four bytes A B C D (big-endian IEEE 754, A = sign and high exponent)
// sit in two consecutive 16-bit registers r[0], r[1]:
//   abcd: r[0] = AB, r[1] = CD   (Modbus big-endian, "high word first")
//   cdab: r[0] = CD, r[1] = AB   (word-swapped, common on PLCs)
//   badc: r[0] = BA, r[1] = DC   (byte-swapped within words)
//   dcba: r[0] = DC, r[1] = BA   (fully little-endian)
// Oracle: 123456.0f = 0x47F12000 → abcd {0x47F1, 0x2000}, cdab {0x2000, 0x47F1},
// badc {0xF147, 0x0020}, dcba {0x0020, 0xF147}.
// The conversion is our own: libmodbus's modbus_get_float_* changed meaning between
// versions (3.0 vs 3.1), so we do not depend on them.
enum class WordOrder : std::uint8_t { abcd, cdab, badc, dcba };

// "ABCD", "CDAB", "BADC", "DCBA" (case-insensitive); nullopt for anything else.
std::optional<WordOrder> parse_word_order(std::string_view text) noexcept;
const char* to_string(WordOrder order) noexcept;

void encode_float32(float value, WordOrder order, std::uint16_t* registers) noexcept;  // 2 regs
float decode_float32(const std::uint16_t* registers, WordOrder order) noexcept;        // 2 regs

}  // namespace excite::hal::modbus
