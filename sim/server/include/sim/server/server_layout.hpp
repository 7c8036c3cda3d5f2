// SPDX-License-Identifier: MIT
#pragma once
// The register layout the plant serves, checked against the plant: one setpoint per plant
// input and one value per plant output (in plant order), one baseline per channel, and the
// two register tables (holding, input) sized to cover every configured register.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "hal/modbus/register_map.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {

/// One value placed in a table: hal's codec (type, word order, scaling) and its address.
struct PlacedValue {
  hal::modbus::Codec codec;
  std::uint32_t address = 0;
  bool input_table = false;  // FC04 input register; otherwise a holding register
};

/// A contiguous block [start, start + count) of one table; count 0 when the table is unused.
struct TableExtent {
  std::uint32_t start = 0;
  std::uint32_t count = 0;
};

struct ServerLayout {
  std::vector<PlacedValue> setpoints;   // plant input i ← setpoints[i] (holding)
  std::vector<PlacedValue> values;      // plant output j → values[j]
  std::uint32_t heartbeat_address = 0;  // holding
  PlacedValue heartbeat_echo;           // uint16, raw counter
  std::optional<std::uint32_t> control_address;
  std::optional<std::uint32_t> command_address;  // holding, uint16 raw
  TableExtent holding;
  TableExtent input;
};

/// Checks the register map on its own: hal's checks (types, word orders, ranges, chunk
/// limits, overlaps among setpoints and among values) with fields prefixed "registers.",
/// then overlaps across each whole table (setpoints, heartbeat, FC03 values, echo and control
/// block in the holding table; FC04 values and echo in the input table).
void check_registers(const ServerRegisters& registers, std::string_view source);

/// Checks the configuration against a plant with `inputs` inputs and `outputs` outputs and
/// places every register. In lock-step mode the heartbeat must be the highest write
/// register, so that a gateway writing in address order (hal's request plan) writes it last
/// and the sample it triggers sees this tick's setpoints. Throws std::invalid_argument
/// "<source>: <field> = <value>, expected <what>".
ServerLayout compile_layout(const ServerConfig& config, int inputs, int outputs, bool lockstep,
                            std::string_view source = "config");

}  // namespace excite::sim::server
