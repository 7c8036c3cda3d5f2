// SPDX-License-Identifier: MIT
#pragma once
// The checks every table meets before the engine streams it — the plan's at configure() and
// arm(), each plan segment's at stage() and in the segment inbox — in one place, so the
// first table and every later one are held to the same rules. No allocation, no exceptions.

#include <cstdint>
#include <span>

#include "firmware/engine/config.hpp"
#include "firmware/signal/table.hpp"

namespace excite::engine {

/// Ok when `table` has `inputs` channels and at least one sample; else
/// "WHAT = 3 channels x 8 samples, expected 2 channels (the configuration's setpoints) and at
/// least 1 sample" (`what`: "table", "segment table").
signal::Status check_table_shape(signal::ConstTableView table, std::uint32_t inputs,
                                 const char* what) noexcept;

/// Ok when baseline[c] + every value of the table's channel c stays within [min, max] of
/// input c (config.inputs channels); else "input[1] baseline + WHAT = [63, 71], expected
/// within [50, 70] (baseline 65)". Precondition: check_table_shape() holds.
signal::Status check_table_range(const EngineConfig& config, std::span<const double> baseline,
                                 signal::ConstTableView table, const char* what) noexcept;

}  // namespace excite::engine
