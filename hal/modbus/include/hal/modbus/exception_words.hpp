// SPDX-License-Identifier: MIT
#pragma once
// Modbus exception replies, in words (Modbus Application Protocol V1.1b3, §7). Codes 1
// (illegal function), 2 (illegal data address) and 3 (illegal data value) answer the request
// itself: the device will refuse it again, so this is a refusal and not a link fault. The
// other codes (4 server device failure, 6 busy, …) are transient, and the gateway's comm
// guard retries them.

#include <cstddef>
#include <cstdint>

namespace excite::hal::modbus {

/// Exception codes counted per code (index = code), 0 … kExceptionCodes − 1.
inline constexpr std::size_t kExceptionCodes = 16;

constexpr bool is_refusal(int exception_code) noexcept {
  return exception_code >= 1 && exception_code <= 3;
}

/// "illegal data value" for 3, …; "exception" for a code without a name.
constexpr const char* exception_name(int code) noexcept {
  switch (code) {
    case 1:
      return "illegal function";
    case 2:
      return "illegal data address";
    case 3:
      return "illegal data value";
    case 4:
      return "server device failure";
    case 5:
      return "acknowledge";
    case 6:
      return "server device busy";
    case 8:
      return "memory parity error";
    case 10:
      return "gateway path unavailable";
    case 11:
      return "gateway target device failed to respond";
    default:
      return "exception";
  }
}

/// What an engineer checks first for a refusal: " — the device's own limits?" for 3, …
constexpr const char* refusal_hint(int code) noexcept {
  return code == 3   ? " — the device's own limits?"
         : code == 2 ? " — is the register map right?"
                     : " — does the device serve this function code?";
}

}  // namespace excite::hal::modbus
