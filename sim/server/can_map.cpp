// SPDX-License-Identifier: MIT
#include "sim/server/can_map.hpp"

#include <stdexcept>

namespace excite::sim::server {

namespace {

// Signal k of a block of float32 pairs starting at identifier `base`.
hal::can::CanSignal pair_signal(const std::string& name, std::uint32_t base, int k) {
  return hal::can::CanSignal{name,      base + static_cast<std::uint32_t>(k / 2),
                             false,     static_cast<std::uint32_t>(4 * (k % 2)),
                             "float32", "little",
                             1.0,       0.0};
}

hal::can::CanSignal counter(const std::string& name, std::uint32_t id) {
  return hal::can::CanSignal{name, id, false, 0, "uint16", "little", 1.0, 0.0};
}

std::string name_of(const std::vector<std::string>& names, int k, const char* prefix) {
  const auto index = static_cast<std::size_t>(k);
  return index < names.size() ? names[index] : prefix + std::to_string(k + 1);
}

}  // namespace

CanLoopMap default_can_map(int inputs, int outputs, const std::vector<std::string>& input_names,
                           const std::vector<std::string>& output_names) {
  if (inputs < 1 || inputs > can_max_inputs || outputs < 1 || outputs > can_max_outputs) {
    throw std::invalid_argument(
        "plant = " + std::to_string(inputs) + " inputs, " + std::to_string(outputs) +
        " outputs, expected 1.." + std::to_string(can_max_inputs) + " inputs and 1.." +
        std::to_string(can_max_outputs) + " outputs for the default CAN frame map");
  }
  const std::uint32_t heartbeat_id = can_setpoint_base + static_cast<std::uint32_t>(inputs + 1) / 2;
  CanLoopMap map;
  for (int i = 0; i < inputs; ++i) {
    const auto s = pair_signal(name_of(input_names, i, "u"), can_setpoint_base, i);
    map.gateway.setpoints.push_back(s);
    map.plant.values.push_back(s);
  }
  map.gateway.heartbeat = counter("heartbeat", heartbeat_id);
  map.plant.values.push_back(counter("heartbeat", heartbeat_id));
  for (int j = 0; j < outputs; ++j) {
    const auto s = pair_signal(name_of(output_names, j, "y"), can_output_base, j);
    map.gateway.values.push_back(s);
    map.plant.setpoints.push_back(s);
  }
  for (int i = 0; i < inputs; ++i) {
    const auto s = pair_signal(name_of(input_names, i, "u") + "_sp", can_readback_base, i);
    map.gateway.values.push_back(s);
    map.plant.setpoints.push_back(s);
  }
  map.gateway.values.push_back(counter("hb_echo", can_echo_id));
  map.plant.heartbeat = counter("hb_echo", can_echo_id);
  return map;
}

}  // namespace excite::sim::server
