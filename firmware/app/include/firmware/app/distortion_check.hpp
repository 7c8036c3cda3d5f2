// SPDX-License-Identifier: MIT
#pragma once
// The dry run's and the arm's distortion check (README "Distortion"): how much of the plan
// the engine would clamp (absolute limits) or rate-limit (max_move), per channel, and the
// refusal when a channel's fraction of rows exceeds gateway.max_distortion (exit 12,
// unless --allow-distortion). Start-up code: allocates.

#include <span>
#include <string>

#include "firmware/app/gateway_config.hpp"
#include "firmware/engine/config.hpp"
#include "firmware/signal/table.hpp"

namespace excite::app {

struct DistortionVerdict {
  std::string report;   // one line per setpoint: rows clamped, rows rate-limited, largest move
  std::string refusal;  // "" when accepted; else why, with the numbers and the way out
};

/// `baseline`: the setpoints at arm (config.inputs values), or empty in a dry run (then
/// clamping is not known yet and only rate limiting is judged). `allow`: --allow-distortion
/// (the verdict still reports; it never refuses).
DistortionVerdict check_distortion(const GatewayConfig& config,
                                   const engine::EngineConfig& engine_config,
                                   signal::ConstTableView table, std::span<const double> baseline,
                                   bool allow);

}  // namespace excite::app
