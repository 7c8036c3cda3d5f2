// SPDX-License-Identifier: MIT
#pragma once
// The excite-plant configuration file (TOML, format in sim/server/README.md): which plant,
// its operating point and noise, and the register map the gateway uses. The per-value
// register fields are hal's (`hal::modbus::RegisterEntry`), checked by hal's own
// `compile_register_map`, so the plant and the gateway agree on every bit.
//
// Every error is a std::invalid_argument whose message reads
//   "<source>: <field> = <value>, expected <what>".

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hal/modbus/register_map.hpp"

namespace excite::sim::server {

/// The plant and its operating point. Exactly one of `library` and `file` is set.
struct PlantSettings {
  std::string library;                  // a library plant name (sim/library), or
  std::string file;                     // a plant file (sim/lti format), relative to the config
  double sample_time_min = 1.0;         // model sample time T, minutes, > 0
  std::vector<double> input_baseline;   // operating point per input (engineering units);
                                        // empty → 0 for every input
  std::vector<double> output_baseline;  // operating point per output; empty → 0
  std::vector<double> noise_variance;   // per output (squared output units); empty → no
                                        // noise; one value → the same on every output
  std::uint64_t noise_seed = 1;
  double tau_high_min = 0.0;  // the design's τ_H and β for the run log's header (firmware/
  double beta = 0.0;          // runlog, TimeScales), minutes and a ratio, ≥ 0; 0: not known
  // What the plant's own controller enforces (README, "Watchdog and input limits"):
  double watchdog_s = 0.0;  // heartbeat watchdog, wall-clock seconds >= 0; 0: off
  // under a controller: every test offset back to zero instead
  std::vector<double> input_min;  // absolute limits per input (engineering units); empty:
  std::vector<double> input_max;  // none. A setpoint write outside is refused (exception 3)
  // The controller in the loop (sim/control's controller file, relative to this file; README,
  // "Closed loop"); empty: the open-loop plant. `excite-plant --controller FILE` overrides it.
  std::string controller;
  // Under a controller: the largest test offset the plant takes, per offset register (the MV
  // offsets in input order, then the CV setpoint offsets in output order; deviations in
  // engineering units, each > 0); a write beyond ±limit is refused with exception 3 and
  // counted, as a setpoint outside input_min/input_max in the open loop. Empty: no bound.
  std::vector<double> offset_limit;
};

/// Number of registers in the control block (holding registers, see README): five fault
/// settings; at +5 the count of values that did not fit their registers, at +6 the count of
/// watchdog trips, at +7 the count of setpoint writes refused for the input limits.
inline constexpr std::uint32_t control_block_size = 8;

/// The register map: hal's map (setpoints FC16, heartbeat, values FC03/FC04) plus what only
/// the plant side has: where the heartbeat is echoed and the fault control block.
struct ServerRegisters {
  hal::modbus::RegisterMap map;  // setpoints in plant-input order, values in plant-output order
  std::uint32_t heartbeat_echo_address = 0;
  int heartbeat_echo_function_code = 3;          // 3 (holding) or 4 (input register)
  std::optional<std::uint32_t> control_address;  // first of control_block_size holding regs
  std::optional<std::uint32_t> command_address;  // holding register an operator writes the
                                                 // gateway's command to (uint16, starts at 0)
  // Closed loop only (a controller configured; README, "Closed loop"), fixed layouts:
  // holding offset_address: the MV test offsets (float32 ABCD, one per input), then the CV
  // setpoint offsets (one per output), written by the gateway; input controller_address:
  // the controller's moves, the applied MVs, the setpoints in force (float32 ABCD), the MV
  // statuses and the mode (uint16); holding controller_switch_address: the operator's
  // switch (uint16: 1 control, 0 off = manual, 3 suspended).
  std::optional<std::uint32_t> offset_address;
  std::optional<std::uint32_t> controller_address;
  std::optional<std::uint32_t> controller_switch_address;
};

struct ServerConfig {
  PlantSettings plant;
  ServerRegisters registers;
  std::filesystem::path base_directory;  // where a relative plant file is looked up
};

/// Parses the configuration text; `source` names it in messages. Checks keys and types
/// (unknown keys are errors) and the register map on its own (hal's checks plus overlaps
/// across the whole holding/input tables, echo and control block included). The plant
/// section may be absent or incomplete here: counts against the plant are checked by
/// `compile_layout` (server_layout.hpp).
ServerConfig parse_server_config(std::string_view toml_text, std::string_view source = "config");

/// Reads and parses a configuration file; base_directory is the file's directory.
ServerConfig load_server_config(const std::filesystem::path& path);

}  // namespace excite::sim::server
