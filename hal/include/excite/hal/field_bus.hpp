// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "excite/hal/status.hpp"

namespace excite::hal {

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
  // counter (the peer watches it change). Status per status.hpp.
  virtual Status write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept = 0;

  // Reads the process values (size == value_count(), engineering units); values are
  // written only when the status is ok.
  virtual Status read(std::span<double> values) noexcept = 0;

  [[nodiscard]] virtual std::size_t setpoint_count() const noexcept = 0;
  [[nodiscard]] virtual std::size_t value_count() const noexcept = 0;

  // A human-readable line about the last non-ok status (fixed buffer owned by the
  // instance, valid until the next call); "" after ok.
  [[nodiscard]] virtual const char* detail() const noexcept = 0;

  // One tick's exchange: write, then read. Returns the first non-ok status.
  Status exchange(std::span<const double> setpoints, std::uint16_t heartbeat,
                  std::span<double> values) noexcept {
    const Status written = write(setpoints, heartbeat);
    if (written != Status::ok) {
      return written;
    }
    return read(values);
  }
};

}  // namespace excite::hal
