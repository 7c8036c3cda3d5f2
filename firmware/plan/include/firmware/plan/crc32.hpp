// SPDX-License-Identifier: MIT
#pragma once
// CRC-32/IEEE 802.3 (reflected polynomial 0xEDB88320, initial and final XOR 0xFFFFFFFF),
// table-driven; check value crc32("123456789") = 0xCBF43926.

#include <cstdint>
#include <span>

namespace excite::plan {

/// Continues a CRC over `bytes`: crc32_update(crc32_update(0, a), b) = crc32(a ‖ b).
std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes);

inline std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return crc32_update(0, bytes);
}

}  // namespace excite::plan
