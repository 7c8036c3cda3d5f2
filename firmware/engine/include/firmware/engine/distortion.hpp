// SPDX-License-Identifier: MIT
#pragma once
// How much of a plan the engine would distort (issue 10 item 5): per channel, the rows
// whose setpoint would be clamped to the absolute limits [min, max] or rate-limited by
// max_move, predicted by running the engine's own setpoint rule (Engine::compute: ramp-in
// over ramp_ticks, target = baseline + ramp · table[k], clamp, then slew) over the whole
// table without a field. Suspensions and communication losses are not predicted.
// Runs at start-up (dry run, arm); no allocation.

#include <array>
#include <cstdint>
#include <span>

#include "firmware/engine/config.hpp"
#include "firmware/signal/table.hpp"

namespace excite::engine {

struct ChannelDistortion {
  std::uint32_t clamped_rows = 0;       // rows whose target left [min, max]
  std::uint32_t rate_limited_rows = 0;  // rows whose move was cut to max_move
  double largest_move = 0.0;            // largest |Δtarget| asked for in one tick
  std::uint32_t largest_move_row = 0;   // the table row asking for it
};

struct Distortion {
  std::uint32_t rows = 0;       // table rows (the denominator of every fraction)
  bool clamping_known = false;  // false without a baseline: only rate limiting is predicted
  std::array<ChannelDistortion, kMaxInputs> channel{};

  /// The larger of the clamped and rate-limited fractions of channel c's rows.
  [[nodiscard]] double fraction(std::uint32_t c) const noexcept;
};

/// Predicts the distortion of `table` under `config`. `baseline` (config.inputs values, the
/// setpoints at arm) makes clamping predictable; empty: only rate limiting (a dry run: the
/// baseline is read at arm). Rate limiting does not depend on the baseline.
Distortion predict_distortion(const EngineConfig& config, signal::ConstTableView table,
                              std::span<const double> baseline) noexcept;

}  // namespace excite::engine
