// SPDX-License-Identifier: MIT
#include "hal/can/bus_timing.hpp"

#include <cstdio>
#include <string>

namespace excite::hal::can {

std::uint32_t worst_case_frame_bits(std::uint32_t dlc, bool extended) noexcept {
  const std::uint32_t g = extended ? 54U : 34U;
  const std::uint32_t payload = 8U * (dlc > 8U ? 8U : dlc);
  return g + payload + 13U + (g + payload - 1U) / 4U;
}

TickLoad tick_load(const CanPlan& plan, std::uint32_t bitrate, double period_s) noexcept {
  TickLoad t;
  for (const can_frame& f : plan.tx) {
    t.bits += worst_case_frame_bits(f.can_dlc, (f.can_id & CAN_EFF_FLAG) != 0);
    ++t.frames;
  }
  for (const RxFrame& f : plan.rx) {
    t.bits += worst_case_frame_bits(f.dlc, (f.id & CAN_EFF_FLAG) != 0);
    ++t.frames;
  }
  t.seconds = bitrate > 0 ? static_cast<double>(t.bits) / static_cast<double>(bitrate) : 0.0;
  t.load = period_s > 0.0 ? t.seconds / period_s : 0.0;
  return t;
}

config::Check check_tick_fits(const CanPlan& plan, std::uint32_t bitrate, double period_s) {
  if (bitrate == 0) {
    return config::Check::valid();
  }
  const TickLoad t = tick_load(plan, bitrate, period_s);
  if (t.load <= 1.0) {
    return config::Check::valid();
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "a rate whose frames fit the tick: %u frames, %u bits at worst per tick need "
                "%.3g ms, the tick is %.3g ms (bus load %.0f %%)",
                t.frames, t.bits, 1e3 * t.seconds, 1e3 * period_s, 100.0 * t.load);
  return config::Check::invalid("can.bitrate", std::to_string(bitrate), text);
}

}  // namespace excite::hal::can
