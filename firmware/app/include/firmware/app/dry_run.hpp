// SPDX-License-Identifier: MIT
#pragma once
// excite-gateway --dry-run's report (README "Command line"): every check passed, and what
// would be written and read each tick — peer, registers or frames, types, du ranges,
// limits, the engine's timing, the first rows — and the predicted distortion per setpoint.
// Nothing is opened or written.

#include <cstdio>

#include "firmware/app/distortion_check.hpp"
#include "firmware/app/gateway.hpp"

namespace excite::app {

/// `gw` after load_plan(); `distortion` the dry run's verdict (accepted, or overridden by
/// `allow_distortion`).
void print_dry_run(std::FILE* out, const Gateway& gw, const DistortionVerdict& distortion,
                   bool allow_distortion);

}  // namespace excite::app
