// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "excite/hal/status.hpp"

namespace excite::hal {

/// Setpoints a refusal can name: the bits of PeerRefusal::setpoints (the engine has at most 8).
inline constexpr std::size_t kMaxRefusalSetpoints = 64;

/// The peer refused a request itself: it would refuse it again, so this is not a link fault
/// and retrying will not help. The transport that saw the refusal fills this record, and only
/// that transport words it. The words are fixed text, so keeping the record on the cyclic path
/// allocates nothing.
struct PeerRefusal {
  bool valid = false;           // false: the last call was not refused
  bool write = false;           // the refused request was a write (else a read)
  std::uint64_t setpoints = 0;  // bit i: the refused write carried setpoint i
  // The request, in the transport's words: "FC16 registers 100..105".
  std::array<char, 64> request{};
  // Why it was refused, in the transport's words:
  // "exception 3, illegal data value — the device's own limits?".
  std::array<char, 128> reason{};
};

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
  // The refusal that made the last call return peer_error; not valid after any other
  // outcome, or after a peer_error the device may not repeat (busy, a malformed reply).
  // Transports whose peers cannot refuse a request never fill it.
  [[nodiscard]] virtual PeerRefusal last_refusal() const noexcept { return {}; }

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
