// SPDX-License-Identifier: MIT
#include "hal/modbus/modbus_field_bus.hpp"

#include <modbus.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace excite::hal::modbus {

namespace {

bool is_exception_reply(int error) noexcept {
  return error >= EMBXILFUN && error <= EMBXGTAR;
}
bool is_malformed_reply(int error) noexcept {
  return error > EMBXGTAR && error <= EMBBADSLAVE;
}

config::Check validate_device(const ModbusDevice& device) {
  if (device.transport != "tcp" && device.transport != "rtu") {
    return config::Check::invalid("device.transport", "\"" + device.transport + "\"",
                                  "\"tcp\" or \"rtu\"");
  }
  if (device.response_timeout_ms < 1 || device.response_timeout_ms > 60000) {
    return config::Check::invalid("device.response_timeout_ms",
                                  std::to_string(device.response_timeout_ms), "1..60000 ms");
  }
  if (device.transport == "tcp") {
    if (device.host.empty()) {
      return config::Check::invalid("device.host", "\"\"", "a host name or address");
    }
    if (device.port < 1 || device.port > 65535) {
      return config::Check::invalid("device.port", std::to_string(device.port), "1..65535");
    }
    if (device.unit_id < 0 || device.unit_id > 255) {
      return config::Check::invalid("device.unit_id", std::to_string(device.unit_id),
                                    "0..255 for Modbus TCP");
    }
    return config::Check::valid();
  }
  if (device.serial_port.empty()) {
    return config::Check::invalid("device.serial_port", "\"\"",
                                  "a serial device path, e.g. /dev/ttyUSB0");
  }
  if (device.baud <= 0) {
    return config::Check::invalid("device.baud", std::to_string(device.baud),
                                  "a positive baud rate, e.g. 19200");
  }
  if (device.parity != "N" && device.parity != "E" && device.parity != "O") {
    return config::Check::invalid("device.parity", "\"" + device.parity + "\"",
                                  "\"N\", \"E\" or \"O\"");
  }
  if (device.data_bits < 5 || device.data_bits > 8) {
    return config::Check::invalid("device.data_bits", std::to_string(device.data_bits), "5..8");
  }
  if (device.stop_bits != 1 && device.stop_bits != 2) {
    return config::Check::invalid("device.stop_bits", std::to_string(device.stop_bits), "1 or 2");
  }
  if (device.unit_id < 1 || device.unit_id > 247) {
    return config::Check::invalid("device.unit_id", std::to_string(device.unit_id),
                                  "1..247 for Modbus RTU (0 is broadcast, which never answers)");
  }
  return config::Check::valid();
}

}  // namespace

config::Check validate(const ModbusConfig& config) {
  if (auto v = validate_device(config.device); !v.ok()) {
    return v;
  }
  RegisterPlan plan;
  return compile_register_map(config.map, plan);
}

ModbusFieldBus::~ModbusFieldBus() {
  release();
}

void ModbusFieldBus::release() noexcept {
  if (ctx_ != nullptr) {
    modbus_close(ctx_);
    modbus_free(ctx_);
    ctx_ = nullptr;
  }
  connected_ = false;
}

void ModbusFieldBus::set_detail(const char* text) noexcept {
  std::snprintf(detail_, sizeof detail_, "%s", text);
}

config::Check ModbusFieldBus::configure(const ModbusConfig& config) {
  release();
  plan_ = RegisterPlan{};
  set_detail("not configured");
  const ModbusDevice& device = config.device;
  if (auto v = validate_device(device); !v.ok()) {
    return v;
  }
  RegisterPlan plan;
  if (auto v = compile_register_map(config.map, plan); !v.ok()) {
    return v;
  }

  std::string where;
  if (device.transport == "tcp") {
    const std::string service = std::to_string(device.port);
    ctx_ = modbus_new_tcp_pi(device.host.c_str(), service.c_str());
    where = "device.host";
    peer_ = "tcp " + device.host + ":" + service + " unit " + std::to_string(device.unit_id);
  } else {
    ctx_ = modbus_new_rtu(device.serial_port.c_str(), device.baud, device.parity[0],
                          device.data_bits, device.stop_bits);
    where = "device.serial_port";
    peer_ = "rtu " + device.serial_port + " slave " + std::to_string(device.unit_id);
  }
  if (ctx_ == nullptr) {
    return config::Check::invalid(
        where, peer_, std::string("a usable device (libmodbus: ") + modbus_strerror(errno) + ")");
  }
  const auto timeout_ms = static_cast<std::uint32_t>(device.response_timeout_ms);
  modbus_set_slave(ctx_, device.unit_id);
  modbus_set_response_timeout(ctx_, timeout_ms / 1000U, (timeout_ms % 1000U) * 1000U);
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);
  if (modbus_connect(ctx_) == -1) {
    const std::string reason = modbus_strerror(errno);
    release();
    return config::Check::invalid(where, peer_,
                                  "a reachable Modbus peer (connect failed: " + reason + ")");
  }
  connected_ = true;
  plan_ = std::move(plan);
  write_image_.assign(plan_.write_image_size, 0);
  read_image_.assign(plan_.read_image_size, 0);
  requests_ = reconnects_ = clamped_ = 0;
  refusal_ = {};
  exception_counts_.fill(0);
  set_detail("");
  return config::Check::valid();
}

StatusCode ModbusFieldBus::ensure_connected() noexcept {
  if (ctx_ == nullptr) {
    set_detail("not configured");
    return StatusCode::unavailable;
  }
  if (connected_) {
    return StatusCode::ok;
  }
  if (modbus_connect(ctx_) == -1) {
    const int error = errno;
    modbus_close(ctx_);
    std::snprintf(detail_, sizeof detail_, "%s: reconnect failed: %s", peer_.c_str(),
                  modbus_strerror(error));
    return StatusCode::link_lost;
  }
  connected_ = true;
  ++reconnects_;
  return StatusCode::ok;
}

StatusCode ModbusFieldBus::fail(const char* operation, const Request* request, int error) noexcept {
  StatusCode status = StatusCode::link_lost;
  if (is_exception_reply(error)) {
    status = StatusCode::peer_error;
    const int code = error - MODBUS_ENOBASE;
    if (is_refusal(code)) keep_refusal(code, operation[0] == 'w', request);
    if (code >= 0 && static_cast<std::size_t>(code) < exception_counts_.size()) {
      ++exception_counts_[static_cast<std::size_t>(code)];
    }
  } else if (is_malformed_reply(error)) {
    modbus_flush(ctx_);
    status = StatusCode::peer_error;
  } else {
    // ETIMEDOUT, EPIPE, ECONNRESET, EBADF and any other system error: start afresh on
    // the next call, so a late reply is never taken for the answer to a new request.
    status = error == ETIMEDOUT ? StatusCode::timeout : StatusCode::link_lost;
    modbus_close(ctx_);
    connected_ = false;
  }
  if (request != nullptr) {
    std::snprintf(detail_, sizeof detail_, "%s: %s FC%02d address %u count %u: %s", peer_.c_str(),
                  operation, request->function_code, static_cast<unsigned>(request->address),
                  static_cast<unsigned>(request->count), modbus_strerror(error));
  } else {
    std::snprintf(detail_, sizeof detail_, "%s: %s: %s", peer_.c_str(), operation,
                  modbus_strerror(error));
  }
  return status;
}

// The refusal in words, and which setpoints a refused write carried (their registers inside
// the request's span of the write image).
void ModbusFieldBus::keep_refusal(int code, bool write, const Request* request) noexcept {
  refusal_ = {};
  refusal_.valid = true;
  refusal_.write = write;
  std::snprintf(refusal_.reason.data(), refusal_.reason.size(), "exception %d, %s%s", code,
                exception_name(code), refusal_hint(code));
  if (request == nullptr) return;
  const unsigned first = request->address;
  std::snprintf(refusal_.request.data(), refusal_.request.size(), "FC%02d registers %u..%u",
                request->function_code, first, first + request->count - 1U);
  for (std::size_t i = 0; write && i < plan_.setpoints.size() && i < kMaxRefusalSetpoints; ++i) {
    const Codec& c = plan_.setpoints[i];
    const std::size_t width = c.type == RegisterType::float32 ? 2U : 1U;
    if (c.offset < request->offset + request->count && c.offset + width > request->offset) {
      refusal_.setpoints |= std::uint64_t{1} << i;
    }
  }
}

StatusCode ModbusFieldBus::write(std::span<const double> setpoints,
                                 std::uint16_t heartbeat) noexcept {
  refusal_.valid = false;  // its words are read only when valid
  if (ctx_ == nullptr) {
    set_detail("not configured");
    return StatusCode::unavailable;
  }
  if (setpoints.size() != plan_.setpoints.size()) {
    std::snprintf(detail_, sizeof detail_, "write: %zu setpoints given, %zu configured",
                  setpoints.size(), plan_.setpoints.size());
    return StatusCode::bad_argument;
  }
  // Encode everything before sending anything: a bad setpoint sends nothing.
  std::uint64_t clamped = 0;
  for (std::size_t i = 0; i < setpoints.size(); ++i) {
    const Codec& codec = plan_.setpoints[i];
    const double value = setpoints[i];
    if (!std::isfinite(value) ||
        (codec.type == RegisterType::float32 && std::fabs(value) > FLT_MAX)) {
      std::snprintf(detail_, sizeof detail_,
                    "write: setpoints[%zu] = %g, expected a finite value%s", i, value,
                    codec.type == RegisterType::float32 ? " within float32 range" : "");
      return StatusCode::bad_argument;
    }
    if (codec.type == RegisterType::float32) {
      encode_float32(static_cast<float>(value), codec.order, &write_image_[codec.offset]);
    } else {
      bool was_clamped = false;
      write_image_[codec.offset] = to_raw(codec, value, was_clamped);
      clamped += was_clamped ? 1U : 0U;
    }
  }
  if (plan_.heartbeat_offset) {
    write_image_[*plan_.heartbeat_offset] = heartbeat;
  }
  clamped_ += clamped;

  if (const StatusCode link = ensure_connected(); link != StatusCode::ok) {
    return link;
  }
  for (const Request& request : plan_.writes) {
    ++requests_;
    if (modbus_write_registers(ctx_, request.address, request.count,
                               &write_image_[request.offset]) == -1) {
      return fail("write", &request, errno);
    }
  }
  detail_[0] = '\0';
  return StatusCode::ok;
}

StatusCode ModbusFieldBus::read(std::span<double> values) noexcept {
  refusal_.valid = false;  // its words are read only when valid
  if (ctx_ == nullptr) {
    set_detail("not configured");
    return StatusCode::unavailable;
  }
  if (values.size() != plan_.values.size()) {
    std::snprintf(detail_, sizeof detail_, "read: room for %zu values given, %zu configured",
                  values.size(), plan_.values.size());
    return StatusCode::bad_argument;
  }
  if (const StatusCode link = ensure_connected(); link != StatusCode::ok) {
    return link;
  }
  for (const Request& request : plan_.reads) {
    ++requests_;
    std::uint16_t* destination = &read_image_[request.offset];
    const int rc =
        request.function_code == 4
            ? modbus_read_input_registers(ctx_, request.address, request.count, destination)
            : modbus_read_registers(ctx_, request.address, request.count, destination);
    if (rc == -1) {
      return fail("read", &request, errno);
    }
  }
  // All requests answered: only now are the caller's values touched.
  for (std::size_t i = 0; i < values.size(); ++i) {
    const Codec& codec = plan_.values[i];
    values[i] = codec.type == RegisterType::float32
                    ? static_cast<double>(decode_float32(&read_image_[codec.offset], codec.order))
                    : from_raw(codec, read_image_[codec.offset]);
  }
  detail_[0] = '\0';
  return StatusCode::ok;
}

StatusCode ModbusFieldBus::write_value(std::size_t index, double value) noexcept {
  refusal_.valid = false;  // its words are read only when valid
  if (ctx_ == nullptr) {
    set_detail("not configured");
    return StatusCode::unavailable;
  }
  if (index >= plan_.values.size() || !std::isfinite(value) || std::fabs(value) > FLT_MAX) {
    std::snprintf(detail_, sizeof detail_,
                  "write_value: values[%zu] = %g, expected a finite value within float32 range "
                  "for one of the %zu configured values",
                  index, value, plan_.values.size());
    return StatusCode::bad_argument;
  }
  if (!value_writable(index)) {
    std::snprintf(detail_, sizeof detail_,
                  "write_value: values[%zu].function_code = %d, expected 3 (a holding register "
                  "the gateway may write back)",
                  index, plan_.values[index].function_code);
    return StatusCode::unavailable;
  }
  const Codec& codec = plan_.values[index];
  std::uint16_t registers[2] = {0, 0};
  if (codec.type == RegisterType::float32) {
    encode_float32(static_cast<float>(value), codec.order, registers);
  } else {
    bool clamped = false;
    registers[0] = to_raw(codec, value, clamped);
  }
  if (const StatusCode link = ensure_connected(); link != StatusCode::ok) {
    return link;
  }
  const Request request{16, codec.address, static_cast<std::uint16_t>(register_count(codec.type)),
                        0};
  ++requests_;
  if (modbus_write_registers(ctx_, request.address, request.count, registers) == -1) {
    return fail("write", &request, errno);
  }
  detail_[0] = '\0';
  return StatusCode::ok;
}

}  // namespace excite::hal::modbus
