// SPDX-License-Identifier: MIT
#pragma once
// The CAN frame map excite-plant serves with `--can IFACE`, derived from the plant's input
// and output counts (sim/server/README.md, "Default CAN frame map"); `excite loop-config
// --transport can` writes the gateway's [can] section from the same function. Classic CAN
// (8 data bytes), 11-bit identifiers, every value float32 little-endian, two per frame:
//
//   0x200 + i/2, byte 4(i%2)   setpoint u_i (gateway → plant), i = 0..n−1
//   0x200 + ⌈n/2⌉, byte 0      heartbeat, uint16, its own frame, sent last (gateway → plant)
//   0x300 + j/2, byte 4(j%2)   output y_j (plant → gateway), j = 0..m−1
//   0x380 + i/2, byte 4(i%2)   readback <u_i>_sp: the setpoint the plant applies
//   0x3F0, byte 0              heartbeat echo, uint16, sent last (plant → gateway)
//
// The setpoint frames have the lower identifiers, so they win arbitration over the values.

#include <cstdint>
#include <string>
#include <vector>

#include "hal/can/frame_map.hpp"

namespace excite::sim::server {

inline constexpr std::uint32_t can_setpoint_base = 0x200;
inline constexpr std::uint32_t can_output_base = 0x300;
inline constexpr std::uint32_t can_readback_base = 0x380;
inline constexpr std::uint32_t can_echo_id = 0x3F0;
inline constexpr int can_max_inputs = 32;   // setpoint and readback frames stay in their block
inline constexpr int can_max_outputs = 64;  // output frames stay below the readbacks

/// Both sides of one CAN loop. The gateway's map: setpoints u_i, the heartbeat, values
/// y_j, then the readbacks <u_i>_sp, then "hb_echo". The plant's map mirrors it: what the
/// gateway receives the plant sends (its "setpoints": y_j then the readbacks, its
/// heartbeat: the echo), what the gateway sends the plant receives (its "values": u_i then
/// "heartbeat").
struct CanLoopMap {
  hal::can::CanFrameMap gateway;
  hal::can::CanFrameMap plant;
};

/// The default CAN map for a plant with `inputs` inputs and `outputs` outputs, channels
/// named by `input_names`/`output_names` when given (else u1.., y1..). Throws
/// std::invalid_argument "plant = ..., expected 1..32 inputs and 1..64 outputs ..." beyond.
CanLoopMap default_can_map(int inputs, int outputs,
                           const std::vector<std::string>& input_names = {},
                           const std::vector<std::string>& output_names = {});

}  // namespace excite::sim::server
