// SPDX-License-Identifier: MIT
#pragma once
// Modbus TCP and RTU behind the transport seam (excite/hal/transport.hpp): the [device]
// keys (host, port, serial_port, baud, parity, data_bits, stop_bits, unit_id,
// response_timeout_ms), the [map] section (register_entry_toml.hpp's map settings), each
// entry's register fields (register_entry_toml.hpp's schema), the registers' carried
// ranges, and the words the gateway describes the peer and its registers with.
// Start-up code (library excite_hal_modbus_toml: reads through base/config and throws).

#include <memory>
#include <string>
#include <string_view>

#include "excite/hal/transport.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

namespace excite::hal::modbus {

/// A Modbus transport's configuration as the gateway's file gives it; `name` is
/// "modbus-tcp" or "modbus-rtu".
std::unique_ptr<TransportConfig> make_transport_config(std::string_view name);

/// The transport's own [device] keys of `d` as TOML lines that the transport's reader reads
/// back into the same fields (beside it, in modbus_transport.cpp): TCP: host, port, unit_id,
/// response_timeout_ms; RTU: serial_port, baud, parity, data_bits, stop_bits, unit_id,
/// response_timeout_ms. The key `transport` is the gateway's to write.
std::string format_device_keys(const ModbusDevice& d);

/// The device and register map `transport` read, or null when it is not a Modbus transport.
const ModbusConfig* modbus_config_of(const TransportConfig& transport) noexcept;

}  // namespace excite::hal::modbus
