// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "base/config/check.hpp"
#include "excite/hal/field_bus.hpp"
#include "hal/modbus/exception_words.hpp"
#include "hal/modbus/register_map.hpp"

struct _modbus;  // libmodbus's modbus_t

namespace excite::hal::modbus {

// Where the peer is and how long to wait for it.
struct ModbusDevice {
  std::string transport = "tcp";  // "tcp" or "rtu"
  // tcp
  std::string host = "127.0.0.1";  // name or address (IPv4/IPv6)
  std::uint32_t port = 502;
  // rtu
  std::string serial_port;  // e.g. /dev/ttyUSB0
  std::int32_t baud = 19200;
  std::string parity = "N";  // N, E or O
  std::int32_t data_bits = 8;
  std::int32_t stop_bits = 1;
  // both
  std::int32_t unit_id = 1;                // TCP unit identifier 0..255; RTU slave 1..247
  std::int32_t response_timeout_ms = 100;  // per request, 1..60000 ms
};

struct ModbusConfig {
  ModbusDevice device;
  RegisterMap map;
};

// Checks device and map without touching the network (what can be checked of an RTU
// configuration on a machine without the serial port).
config::Check validate(const ModbusConfig& config);

// The field bus over Modbus TCP or RTU. Lifecycle: configure() validates, compiles the
// register map, sizes every buffer and connects; write()/read() then never allocate.
// libmodbus's own error recovery is off; this class reconnects instead:
//   ETIMEDOUT                  → timeout;   the link is closed, reconnected on the next call
//   EPIPE, ECONNRESET, EBADF   → link_lost; likewise
//   Modbus exception reply     → peer_error; link kept; exception_counts() counts it; 1, 2
//                                and 3 (the device refused the request) also fill
//                                last_refusal(): the request, the code in words and the
//                                setpoints the request carried (4, 6: transient, not filled)
//   malformed reply (CRC, …)   → peer_error; pending input flushed, link kept
//   reconnect fails            → link_lost; tried again on the next call
// One context per thread: an instance is not thread-safe; give each thread its own.
class ModbusFieldBus final : public FieldBus {
 public:
  ModbusFieldBus() = default;
  ~ModbusFieldBus() override;

  // May be called again to reconfigure (closes the previous connection first).
  // An unreachable device fails here, naming host/port (or serial port) and the reason.
  config::Check configure(const ModbusConfig& config);

  StatusCode write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept override;
  StatusCode read(std::span<double> values) noexcept override;
  // A holding-register value (function_code = 3) is written with FC16; an input register
  // (function_code = 4) cannot be written: unavailable.
  StatusCode write_value(std::size_t index, double value) noexcept override;
  [[nodiscard]] bool value_writable(std::size_t index) const noexcept override {
    return index < plan_.values.size() && plan_.values[index].function_code == 3;
  }
  [[nodiscard]] std::size_t setpoint_count() const noexcept override {
    return plan_.setpoints.size();
  }
  [[nodiscard]] std::size_t value_count() const noexcept override { return plan_.values.size(); }
  [[nodiscard]] const char* detail() const noexcept override { return detail_; }
  [[nodiscard]] PeerRefusal last_refusal() const noexcept override { return refusal_; }
  // Exception replies since configuration, per code (exception_words.hpp).
  [[nodiscard]] std::span<const std::uint64_t> exception_counts() const noexcept {
    return {exception_counts_.data(), exception_counts_.size()};
  }

  [[nodiscard]] const RegisterPlan& plan() const noexcept { return plan_; }
  [[nodiscard]] std::uint64_t requests() const noexcept { return requests_; }      // sent
  [[nodiscard]] std::uint64_t reconnects() const noexcept { return reconnects_; }  // successful
  [[nodiscard]] std::uint64_t clamped_setpoints() const noexcept { return clamped_; }
  [[nodiscard]] bool connected() const noexcept { return connected_; }

 private:
  void release() noexcept;
  StatusCode ensure_connected() noexcept;
  StatusCode fail(const char* operation, const Request* request, int error) noexcept;
  void keep_refusal(int code, bool write, const Request* request) noexcept;
  void set_detail(const char* text) noexcept;

  _modbus* ctx_ = nullptr;
  bool connected_ = false;
  RegisterPlan plan_;
  std::vector<std::uint16_t> write_image_;
  std::vector<std::uint16_t> read_image_;
  std::string peer_;  // "tcp 127.0.0.1:502 unit 1" for messages
  std::uint64_t requests_ = 0;
  std::uint64_t reconnects_ = 0;
  std::uint64_t clamped_ = 0;
  char detail_[256] = "not configured";
  PeerRefusal refusal_{};
  std::array<std::uint64_t, kExceptionCodes> exception_counts_{};
};

}  // namespace excite::hal::modbus
