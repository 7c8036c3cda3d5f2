// SPDX-License-Identifier: MIT
#pragma once
// Start-up: plan file → checked plan → table in fixed storage (firmware/plan, firmware/signal).
// Runs before anything is written to the field; every refusal names what was found and
// what was expected.

#include <cstdint>
#include <span>

#include "firmware/plan/plan.hpp"
#include "firmware/signal/status.hpp"
#include "firmware/signal/table.hpp"

namespace excite::engine {

/// Decodes the file (magic, version, checksum, contents: plan::decode) and checks that the
/// plan has `expected_channels` channels (the configuration's setpoints) and that its
/// table fits `capacity` values (signal::kTableCapacity on the gateway).
signal::Status load_plan(std::span<const std::uint8_t> file, std::uint32_t expected_channels,
                         std::size_t capacity, plan::Plan& out);

/// Generates the plan's table into `storage` with the firmware signal core (the same code
/// as the host's preview, so bit-identical) and checks every value against the plan's
/// deviation limits (plan::check_limits). `scratch` needs signal::scratch_size(recipe)
/// doubles. On success `table` views the front of `storage`.
signal::Status make_table(const plan::Plan& plan, std::span<double> storage,
                          std::span<double> scratch, signal::TableView& table);

}  // namespace excite::engine
