// SPDX-License-Identifier: MIT
#pragma once
// Plan segments: a running gateway takes the next plan (the same plan file format) without a
// bump. These checks run off the cyclic path (the app's segment inbox thread), before a
// segment's table is handed to Engine::stage(); each refusal names the field, the value and
// what was expected, and leaves the running segment untouched.

#include <span>

#include "firmware/engine/config.hpp"
#include "firmware/plan/plan.hpp"
#include "firmware/signal/status.hpp"
#include "firmware/signal/table.hpp"

namespace excite::engine {

/// The next segment must have the running plan's channels (count, names, limits) and
/// sample time: `segment.channels[1].max = 3, expected 2 (the running plan's)`.
signal::Status check_segment(const plan::Plan& running, const plan::Plan& next);

/// As arm() checks the first table: baseline + the segment table's extremes must stay
/// within [min, max] of every input (`baseline` from the armed engine, config.inputs values).
signal::Status check_segment_table(const EngineConfig& config, std::span<const double> baseline,
                                   signal::ConstTableView table);

}  // namespace excite::engine
