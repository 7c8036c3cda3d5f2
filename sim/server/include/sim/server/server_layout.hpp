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

/// The closed-loop registers (README, "Closed loop"), placed from the three addresses of
/// ServerRegisters; every float32 is ABCD and carries a deviation from the operating point.
///   holding W + 2i       MV i's test offset              (W = offset_address, n inputs)
///   holding W + 2n + 2j  CV j's setpoint offset          (m outputs)
///   input   R + 2i       controller move u_ctrl,i        (R = controller_address)
///   input   R + 2n + 2i  applied MV du_i (what the plant got)
///   input   R + 4n + 2j  CV j's setpoint in force
///   input   R + 4n + 2m + i  MV i's status (uint16: 0 ok, 1 clamped low, 2 clamped high,
///                            3 windup, 4 manual)
///   input   R + 5n + 2m  the controller's mode (uint16: 0 off, 1 control, 2 test, 3 suspended)
///   holding S            the operator's switch (uint16: 1 control, 0 off, 3 suspended)
struct ClosedLoopLayout {
  std::vector<PlacedValue> mv_offsets;
  std::vector<PlacedValue> sp_offsets;
  std::vector<PlacedValue> moves;
  std::vector<PlacedValue> applied;
  std::vector<PlacedValue> setpoints;  // in force
  std::vector<PlacedValue> status;
  PlacedValue mode;
  PlacedValue controller_switch;
  std::uint32_t offset_start = 0;  // the written block [offset_start, offset_start + offset_count)
  std::uint32_t offset_count = 0;
};

/// Registers in the offset block (2 per MV, 2 per CV) and in the controller's read block.
constexpr std::uint32_t offset_block_size(int inputs, int outputs) {
  return 2 * static_cast<std::uint32_t>(inputs + outputs);
}
constexpr std::uint32_t controller_block_size(int inputs, int outputs) {
  return 5 * static_cast<std::uint32_t>(inputs) + 2 * static_cast<std::uint32_t>(outputs) + 1;
}

struct ServerLayout {
  std::vector<PlacedValue> setpoints;   // plant input i ← setpoints[i] (holding)
  std::vector<PlacedValue> values;      // plant output j → values[j]
  std::uint32_t heartbeat_address = 0;  // holding
  PlacedValue heartbeat_echo;           // uint16, raw counter
  std::optional<std::uint32_t> control_address;
  std::optional<std::uint32_t> command_address;  // holding, uint16 raw
  std::optional<ClosedLoopLayout> closed_loop;   // only with a controller
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
/// and the sample it triggers sees this tick's setpoints (the test offsets too, under a
/// controller). With `config.plant.controller` set, the three closed-loop addresses are
/// required and placed (ClosedLoopLayout); without it, any of them is refused. Throws
/// std::invalid_argument
/// "<source>: <field> = <value>, expected <what>".
ServerLayout compile_layout(const ServerConfig& config, int inputs, int outputs, bool lockstep,
                            std::string_view source = "config");

}  // namespace excite::sim::server
