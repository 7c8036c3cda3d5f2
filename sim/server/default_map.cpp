// SPDX-License-Identifier: MIT
#include "sim/server/default_map.hpp"

#include <stdexcept>
#include <string>

namespace excite::sim::server {

ServerRegisters default_registers(int inputs, int outputs,
                                  const std::vector<std::string>& input_names,
                                  const std::vector<std::string>& output_names) {
  if (inputs < 1 || inputs > default_max_inputs || outputs < 1 || outputs > default_max_outputs) {
    throw std::invalid_argument(
        "plant = " + std::to_string(inputs) + " inputs, " + std::to_string(outputs) +
        " outputs: expected 1.." + std::to_string(default_max_inputs) + " inputs and 1.." +
        std::to_string(default_max_outputs) +
        " outputs for the default register map (write a --config for larger plants)");
  }
  ServerRegisters regs;
  for (int i = 0; i < inputs; ++i) {
    hal::modbus::RegisterEntry e;
    e.name = static_cast<std::size_t>(i) < input_names.size()
                 ? input_names[static_cast<std::size_t>(i)]
                 : "u" + std::to_string(i + 1);
    e.address = default_setpoint_base + 2 * static_cast<std::uint32_t>(i);
    e.function_code = 16;
    regs.map.setpoints.push_back(e);
  }
  for (int j = 0; j < outputs; ++j) {
    hal::modbus::RegisterEntry e;
    e.name = static_cast<std::size_t>(j) < output_names.size()
                 ? output_names[static_cast<std::size_t>(j)]
                 : "y" + std::to_string(j + 1);
    e.address = default_value_base + 2 * static_cast<std::uint32_t>(j);
    e.function_code = 4;
    regs.map.values.push_back(e);
  }
  regs.map.heartbeat_address = default_setpoint_base + 2 * static_cast<std::uint32_t>(inputs);
  regs.heartbeat_echo_address = default_echo_address;
  regs.heartbeat_echo_function_code = 4;
  regs.command_address = default_command_address;
  regs.control_address = default_control_address;
  return regs;
}

}  // namespace excite::sim::server
