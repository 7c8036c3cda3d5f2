// SPDX-License-Identifier: MIT
#include "firmware/engine/distortion.hpp"

#include <algorithm>
#include <cmath>

namespace excite::engine {

double Distortion::fraction(std::uint32_t c) const noexcept {
  if (rows == 0) return 0.0;
  const ChannelDistortion& d = channel[c];
  return static_cast<double>(std::max(d.clamped_rows, d.rate_limited_rows)) /
         static_cast<double>(rows);
}

Distortion predict_distortion(const EngineConfig& config, signal::ConstTableView table,
                              std::span<const double> baseline) noexcept {
  Distortion d;
  d.rows = table.samples;
  d.clamping_known = baseline.size() >= config.inputs;
  const double step = config.ramp_ticks == 0 ? 1.0 : 1.0 / config.ramp_ticks;
  for (std::uint32_t c = 0; c < config.inputs && c < table.channels; ++c) {
    const InputLimits& in = config.input[c];
    ChannelDistortion& out = d.channel[c];
    // Deviations from the baseline: the setpoint rule is the same shifted by it.
    const double base = d.clamping_known ? baseline[c] : 0.0;
    double ramp = 0.0;
    double previous = 0.0;         // setpoint − baseline written last tick (arm: 0)
    double previous_target = 0.0;  // what was asked last tick
    for (std::uint32_t k = 0; k < table.samples; ++k) {
      ramp = std::min(1.0, ramp + step);
      double target = ramp * table.at(k, c);
      if (d.clamping_known && (base + target < in.min || base + target > in.max)) {
        target = std::clamp(base + target, in.min, in.max) - base;
        ++out.clamped_rows;
      }
      const double asked = std::abs(target - previous_target);
      if (asked > out.largest_move) {
        out.largest_move = asked;
        out.largest_move_row = k;
      }
      previous_target = target;
      if (target - previous > in.max_move) {
        target = previous + in.max_move;
        ++out.rate_limited_rows;
      } else if (previous - target > in.max_move) {
        target = previous - in.max_move;
        ++out.rate_limited_rows;
      }
      previous = target;
    }
  }
  return d;
}

}  // namespace excite::engine
