// SPDX-License-Identifier: MIT
#include "sim/server/default_map.hpp"

#include <stdexcept>
#include <string>

#include "sim/server/server_layout.hpp"

namespace excite::sim::server {

ServerRegisters default_registers(int inputs, int outputs,
                                  const std::vector<std::string>& input_names,
                                  const std::vector<std::string>& output_names, bool closed_loop) {
  if (inputs < 1 || inputs > default_max_inputs || outputs < 1 || outputs > default_max_outputs) {
    throw std::invalid_argument(
        "plant = " + std::to_string(inputs) + " inputs, " + std::to_string(outputs) +
        " outputs, expected 1.." + std::to_string(default_max_inputs) + " inputs and 1.." +
        std::to_string(default_max_outputs) +
        " outputs for the default register map (write a --config for larger plants)");
  }
  // Entry k of a block of float32 ABCD registers: its given name, or prefix + (k + 1).
  const auto entry = [](const std::vector<std::string>& names, int k, const char* prefix,
                        std::uint32_t base, int function_code) {
    hal::modbus::RegisterEntry e;
    const auto index = static_cast<std::size_t>(k);
    e.name = index < names.size() ? names[index] : prefix + std::to_string(k + 1);
    e.address = base + 2 * static_cast<std::uint32_t>(k);
    e.function_code = function_code;
    return e;
  };
  ServerRegisters regs;
  for (int i = 0; i < inputs; ++i) {
    regs.map.setpoints.push_back(entry(input_names, i, "u", default_setpoint_base, 16));
  }
  for (int j = 0; j < outputs; ++j) {
    regs.map.values.push_back(entry(output_names, j, "y", default_value_base, 4));
  }
  regs.map.heartbeat_address = default_setpoint_base + 2 * static_cast<std::uint32_t>(inputs);
  regs.heartbeat_echo_address = default_echo_address;
  regs.heartbeat_echo_function_code = 4;
  regs.command_address = default_command_address;
  regs.control_address = default_control_address;
  if (closed_loop) {
    regs.offset_address = default_offset_address;
    regs.controller_address = default_controller_address;
    regs.controller_switch_address = default_switch_address;
    regs.map.heartbeat_address = default_offset_address + offset_block_size(inputs, outputs);
  }
  return regs;
}

}  // namespace excite::sim::server
