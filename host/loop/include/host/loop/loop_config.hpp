// SPDX-License-Identifier: MIT
#pragma once
// One register map for both sides of the loop: the excite-plant configuration
// (sim/server/README.md) and the excite-gateway configuration (firmware/app/README.md) made
// from one description — the plant and sim/server's default register map — so no address
// is typed twice. `excite loop-config` writes them; the campaign streams through them.

#include <cstdint>
#include <string>
#include <vector>

namespace excite::host {

struct LoopConfigOptions {
  std::string plant;               // what sim::make_plant takes
  std::string host = "127.0.0.1";  // the plant server's address, as the gateway dials it
  std::uint32_t port = 1502;       // its TCP port
  double input_range = 0.0;        // ± deviation allowed on every input; 0: the case study's
  double max_move = 0.0;           // largest change per tick; 0: 2 × input_range
  double output_range = 0.0;       // ± test limits around each output's baseline; 0: none
  double sample_time_min = 0.0;    // 0: the case study's (1 without one)
  double noise_var = -1.0;         // < 0: the case study's (0 without one)
  std::uint64_t seed = 1;
  double period_s = 0.0;    // gateway tick period; 0: the plan's sample time
  double watchdog_s = 3.0;  // the plant's heartbeat watchdog, wall-clock seconds; 0: off
  std::string transport = "modbus-tcp";  // or "can": the default CAN frame map (can_map.hpp)
  std::string can_interface = "vcan0";   // transport can: the SocketCAN interface
  // Closed loop (issue 42 §3): the controller file excite-plant runs (plant.controller) and
  // which test offsets the gateway writes: "setpoint" (CV setpoint offsets), "mv" (MV test
  // offsets) or "both". Empty controller: the open-loop pair, unchanged.
  std::string controller;
  std::string offsets = "setpoint";
  double controller_timeout_s = 60.0;  // the gateway's [closed_loop] controller_timeout_s
};

struct LoopConfigPair {
  std::string plant_toml;    // excite-plant --config
  std::string gateway_toml;  // excite-gateway --config
  // What was changed from the options, said to the user (one line each): the watchdog
  // raised to two tick periods.
  std::vector<std::string> notes;
};

/// Both configurations as TOML text. With transport "can" the gateway side is the [can]
/// section and frames of sim/server's default CAN frame map (the map excite-plant --can
/// serves); plant.toml is the same (its watchdog and input limits apply over CAN too).
/// Throws std::invalid_argument naming the option, its
/// value and what was expected (NaN, negative, a port beyond 65535, a plant without a case
/// study and no input range), or what sim::make_plant throws for an unknown plant.
/// With a controller: plant.toml names it (absolute path) and serves the closed-loop
/// registers of sim/server's default map (no input limits: the controller's MV limits bound
/// the applied MVs); gateway.toml writes the offsets (`<mv>_off`, `<cv>_spoff`, limits ±
/// input range, CV setpoint offsets ± output range or the input range), verifies them by
/// readback and reads the controller's mode, MV statuses, moves, applied MVs and setpoints
/// in force ([closed_loop]). The controller file is checked against the plant first (its
/// errors by name). Modbus only.
LoopConfigPair make_loop_config(const LoopConfigOptions& options);

}  // namespace excite::host
