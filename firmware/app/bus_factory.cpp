// SPDX-License-Identifier: MIT
#include "firmware/app/bus_factory.hpp"

#include "hal/can/can_field_bus.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

namespace excite::app {

BusResult make_field_bus(const GatewayConfig& config, const hal::Clock& clock, bool lockstep) {
  BusResult result;
  if (config.transport == Transport::can) {
    auto bus = std::make_unique<hal::can::CanFieldBus>(clock);
    hal::can::CanConfig can = config.can;
    for (std::size_t i = 0; lockstep && i < config.values.size(); ++i) {
      if (config.values[i].role == ValueRole::heartbeat_echo) can.await_echo = i;
    }
    if (const hal::Validation v = bus->configure(can); !v.ok()) {
      result.error = v.message();
      return result;
    }
    result.bus = std::move(bus);
    return result;
  }
  auto bus = std::make_unique<hal::modbus::ModbusFieldBus>();
  if (const hal::Validation v = bus->configure(config.modbus); !v.ok()) {
    result.error = v.message();
    return result;
  }
  result.bus = std::move(bus);
  return result;
}

std::string describe_peer(const GatewayConfig& config) {
  if (config.transport == Transport::can) {
    return "can " + config.can.interface + ", value frames stale after " +
           std::to_string(config.can.value_timeout_ms) + " ms";
  }
  const auto& d = config.modbus.device;
  if (config.transport == Transport::modbus_tcp) {
    return "modbus-tcp " + d.host + ":" + std::to_string(d.port) + " unit " +
           std::to_string(d.unit_id) + ", response timeout " +
           std::to_string(d.response_timeout_ms) + " ms";
  }
  return "modbus-rtu " + d.serial_port + " " + std::to_string(d.baud) + " baud " + d.parity +
         std::to_string(d.data_bits) + std::to_string(d.stop_bits) + " unit " +
         std::to_string(d.unit_id) + ", response timeout " + std::to_string(d.response_timeout_ms) +
         " ms";
}

}  // namespace excite::app
