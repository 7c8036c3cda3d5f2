// SPDX-License-Identifier: MIT
#pragma once
// How long one tick's frames occupy a real CAN bus (classic CAN, hal/can/README.md "Timing"):
// the worst case of each data frame with bit stuffing, the frames the gateway sends (one per
// setpoint identifier) and those its peer answers with (one per value identifier), against
// the bit rate and the tick period. Pure arithmetic, no I/O.

#include <cstdint>

#include "base/config/check.hpp"
#include "hal/can/frame_map.hpp"

namespace excite::hal::can {

/// Worst-case bits of one classic CAN data frame carrying `dlc` bytes (0..8), bit stuffing
/// and the 3-bit interframe space included: g + 8·dlc + 13 + ⌊(g + 8·dlc − 1)/4⌋, g = 34 for
/// an 11-bit identifier, 54 for a 29-bit one (Davis, Burns, Bril, Lukkien, "Controller Area
/// Network (CAN) schedulability analysis", Real-Time Systems 35, 2007, §3). 8 bytes: 135
/// bits (11-bit) or 160 bits (29-bit).
std::uint32_t worst_case_frame_bits(std::uint32_t dlc, bool extended) noexcept;

struct TickLoad {
  std::uint32_t frames = 0;  // setpoint frames + value frames per tick
  std::uint32_t bits = 0;    // their worst-case bits
  double seconds = 0.0;      // bits / bit rate
  double load = 0.0;         // seconds / tick period (1: the bus is busy the whole tick)
};

/// One tick of `plan` on a bus of `bitrate` bit/s (> 0) ticking every `period_s` (> 0).
TickLoad tick_load(const CanPlan& plan, std::uint32_t bitrate, double period_s) noexcept;

/// Refuses (field "can.bitrate") a configuration whose frames of one tick, at their worst
/// case, need longer than the tick: the bus could not carry them before the next tick's.
/// bitrate 0 (a virtual bus, vcan) is not checked.
config::Check check_tick_fits(const CanPlan& plan, std::uint32_t bitrate, double period_s);

}  // namespace excite::hal::can
