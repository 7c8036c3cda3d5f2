// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "excite/hal/status.hpp"

namespace excite::hal {

// A peer's exception reply (Modbus), kept by the bus for its caller. Codes 1 (illegal
// function), 2 (illegal data address) and 3 (illegal data value) are the device's answer to
// the request itself — it will refuse it again: a refusal, not a link fault. The others
// (4 server device failure, 6 busy, …) are transient: the comm guard retries.
struct PeerException {
  int code = 0;               // the exception code; 0: none
  bool write = false;         // the refused request was a write (else a read)
  std::uint8_t function = 0;  // its function code
  std::uint32_t address = 0;  // its first register
  std::uint16_t count = 0;    // its register count
};

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

/// Exception codes counted per code (index = code), 0 … kExceptionCodes − 1.
inline constexpr std::size_t kExceptionCodes = 16;

// A field bus as the gateway engine sees it: once per tick it writes the setpoints and a
// heartbeat and reads the process values, all in engineering units in the order of the
// configured map. Implementations (Modbus TCP/RTU, SocketCAN) are configured with their
// own map before use; configuration may allocate and open connections, the calls below
// must not allocate and return within the transport's response timeout.
// One instance per thread: an instance owns its connection and is not thread-safe.
class FieldBus {
 public:
  virtual ~FieldBus() = default;
  FieldBus() = default;
  FieldBus(const FieldBus&) = delete;
  FieldBus& operator=(const FieldBus&) = delete;

  // Writes setpoints (size == setpoint_count(), engineering units) and the heartbeat
  // counter (the peer watches it change). StatusCode per status.hpp.
  virtual StatusCode write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept = 0;

  // Reads the process values (size == value_count(), engineering units); values are
  // written only when the status is ok.
  virtual StatusCode read(std::span<double> values) noexcept = 0;

  [[nodiscard]] virtual std::size_t setpoint_count() const noexcept = 0;
  [[nodiscard]] virtual std::size_t value_count() const noexcept = 0;

  // A human-readable line about the last non-ok status (fixed buffer owned by the
  // instance, valid until the next call); "" after ok.
  [[nodiscard]] virtual const char* detail() const noexcept = 0;

  // Writes one process value back (index < value_count(), engineering units): the
  // operator command register's acknowledgement (the gateway clears it after acting on a
  // command). Only a value the transport can write (value_writable); others: unavailable.
  virtual StatusCode write_value(std::size_t /*index*/, double /*value*/) noexcept {
    return StatusCode::unavailable;
  }
  [[nodiscard]] virtual bool value_writable(std::size_t /*index*/) const noexcept { return false; }
  // The exception reply that made the last call return peer_error (code 0 after any other
  // outcome). Transports without exception replies: always none.
  [[nodiscard]] virtual PeerException last_exception() const noexcept { return {}; }

  // Exception replies since configuration, per code (kExceptionCodes entries; empty for
  // transports without them).
  [[nodiscard]] virtual std::span<const std::uint64_t> exception_counts() const noexcept {
    return {};
  }

  // One tick's exchange: write, then read. Returns the first non-ok status.
  StatusCode exchange(std::span<const double> setpoints, std::uint16_t heartbeat,
                      std::span<double> values) noexcept {
    const StatusCode written = write(setpoints, heartbeat);
    if (written != StatusCode::ok) {
      return written;
    }
    return read(values);
  }
};

}  // namespace excite::hal
