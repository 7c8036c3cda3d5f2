// SPDX-License-Identifier: MIT
#include "firmware/app/bus_factory.hpp"

#include <cstdio>
#include <cstring>

#include "hal/can/bus_timing.hpp"
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
    result.can = bus.get();
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

std::string check_bus_timing(const GatewayConfig& config, double period_s) {
  if (config.transport != Transport::can || config.can.bitrate == 0) return "";
  hal::can::CanPlan plan;
  if (!hal::can::compile_frame_map(config.can.map, plan).ok()) return "";  // checked at load
  const hal::Validation v = hal::can::check_tick_fits(plan, config.can.bitrate, period_s);
  return v.ok() ? "" : v.message();
}

std::string bus_counts_report(const BusResult& made) {
  const hal::can::CanFieldBus* can = made.can;
  if (can == nullptr) return "";
  const hal::can::CanCounters c = can->counters();
  const auto hex = [](unsigned id) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%X", id);
    return std::string(text);
  };
  std::string out = "can " + can->interface_name() + ": value frames refused for their DLC " +
                    std::to_string(c.short_frames);
  if (c.short_frames > 0) {
    out += " (first " + hex(c.first_short_id) + " DLC " + std::to_string(c.first_short_dlc) + ")";
  }
  out += ", frames of the gateway's own identifiers from another node " +
         std::to_string(c.own_id_frames);
  if (c.own_id_frames > 0) out += " (first " + hex(c.first_own_id) + ")";
  out += ", sends refused " + std::to_string(c.send_failures);
  if (c.send_failures > 0) out += std::string(" (last: ") + std::strerror(c.last_send_error) + ")";
  out += ", reads with a value frame stale or missing " + std::to_string(c.stale_reads) +
         ", echoes missing " + std::to_string(c.echo_timeouts) + ", error frames " +
         std::to_string(c.error_frames);
  return out;
}

std::string describe_peer(const GatewayConfig& config) {
  if (config.transport == Transport::can) {
    return "can " + config.can.interface +
           (config.can.bitrate > 0 ? " " + std::to_string(config.can.bitrate) + " bit/s" : "") +
           ", value frames stale after " + std::to_string(config.can.value_timeout_ms) + " ms";
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
