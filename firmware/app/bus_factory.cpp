// SPDX-License-Identifier: MIT
#include "firmware/app/bus_factory.hpp"

#include <optional>
#include <string>

namespace excite::app {

BusResult make_field_bus(const GatewayConfig& config, const hal::Clock& clock, bool lockstep) {
  if (!config.transport) {
    BusResult none;
    none.error = "device.transport = (none), expected a transport read from the configuration";
    return none;
  }
  std::optional<std::size_t> await_echo;
  for (std::size_t i = 0; lockstep && i < config.values.size(); ++i) {
    if (config.values[i].role == ValueRole::heartbeat_echo) await_echo = i;
  }
  return config.transport->make_bus(clock, await_echo);
}

std::string check_written_values(const GatewayConfig& config, const hal::FieldBus& bus) {
  for (std::size_t i = 0; i < config.values.size(); ++i) {
    if (config.values[i].acknowledge && !bus.value_writable(i)) {
      return "values[" + std::to_string(i) +
             "].acknowledge = \"clear\", expected a command value " +
             "the transport can write back (Modbus: a holding register, function_code = 3; the " +
             "CAN transport writes no value)";
    }
  }
  return "";
}

std::string check_bus_timing(const GatewayConfig& config, double period_s) {
  return config.transport ? config.transport->check_tick(period_s) : "";
}

std::string bus_counts_report(const BusResult& made) {
  return made.bus && made.counts_report ? made.counts_report() : "";
}

std::string describe_peer(const GatewayConfig& config) {
  return config.transport ? config.transport->describe_peer() : "a bus handed over built";
}

}  // namespace excite::app
