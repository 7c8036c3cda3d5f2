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
/// table fits `capacity` values (signal::kTableCapacity on the gateway). `streams`: what the
/// setpoints are — MV moves (open_loop, the default), CV setpoint offsets (setpoint) or MV
/// offsets on a running controller (mv). An open-loop plan streams anywhere (its table is
/// in the setpoints' units); a closed-loop plan (version 4) only where its excitation is
/// `streams` — a setpoint plan is never played as MV moves, nor an MV dither as setpoints.
signal::Status load_plan(std::span<const std::uint8_t> file, std::uint32_t expected_channels,
                         std::size_t capacity, plan::Plan& out,
                         plan::Excitation streams = plan::Excitation::open_loop);

/// Generates the plan's table into `storage` with the firmware signal core (the same code
/// as the host's preview, so bit-identical) and checks every value against the plan's
/// deviation limits (plan::check_limits). `scratch` needs signal::scratch_size(recipe)
/// doubles. On success `table` views the front of `storage`.
signal::Status make_table(const plan::Plan& plan, std::span<double> storage,
                          std::span<double> scratch, signal::TableView& table);

}  // namespace excite::engine
