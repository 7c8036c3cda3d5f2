// SPDX-License-Identifier: MIT
#pragma once
// The register map excite-plant serves when no configuration file is given, derived from the
// plant's input and output counts (sim/server/README.md, "Default register map"). Every
// value is float32, word order ABCD; the gateway configuration written by `excite
// loop-config` uses the same addresses.
//
//   holding 100 + 2i   setpoint u_i (FC16 write, FC03 read back), i = 0..inputs−1
//   holding 100 + 2n   heartbeat (uint16, written last, n = inputs)
//   holding 301        command register (uint16, 0 = none; an operator writes it)
//   holding 400..407   control block (faults, misfit/watchdog/refused-write counters)
//   input   200 + 2j   output y_j (FC04), j = 0..outputs−1
//   input   300        heartbeat echo (uint16)
//
// Under a controller (closed_loop; README, "Closed loop") the same, and:
//   holding 410        the operator's controller switch (uint16)
//   holding 500 + …    the test offsets: MV i at 500 + 2i, CV j's setpoint offset at
//                      500 + 2n + 2j (m = outputs)
//   holding 500 + 2(n + m)  the heartbeat (moved: still the highest register written)
//   input   500 + …    the controller's block (server_layout.hpp, ClosedLoopLayout)

#include <cstdint>
#include <string>
#include <vector>

#include "sim/server/server_config.hpp"

namespace excite::sim::server {

inline constexpr std::uint32_t default_setpoint_base = 100;
inline constexpr std::uint32_t default_value_base = 200;
inline constexpr std::uint32_t default_echo_address = 300;
inline constexpr std::uint32_t default_command_address = 301;
inline constexpr std::uint32_t default_control_address = 400;
inline constexpr std::uint32_t default_switch_address = 410;
inline constexpr std::uint32_t default_offset_address = 500;
inline constexpr std::uint32_t default_controller_address = 500;
inline constexpr int default_max_inputs = 99;   // setpoints + heartbeat stay below 300
inline constexpr int default_max_outputs = 50;  // values stay below the echo at 300

/// The default map for a plant with `inputs` inputs and `outputs` outputs, entries named
/// by `input_names`/`output_names` when given (sizes must then match). Throws
/// std::invalid_argument "plant = ..., expected at most 99 inputs and 50 outputs ..." beyond
/// the table's room. `closed_loop`: the map under a controller (above).
ServerRegisters default_registers(int inputs, int outputs,
                                  const std::vector<std::string>& input_names = {},
                                  const std::vector<std::string>& output_names = {},
                                  bool closed_loop = false);

}  // namespace excite::sim::server
