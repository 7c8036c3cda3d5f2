// SPDX-License-Identifier: MIT
#pragma once
// The field bus of the configured transport, built and configured at start-up (allocates,
// connects or opens the device, writes nothing) by the transport itself
// (hal::TransportConfig::make_bus); this room only says which value carries the echo.

#include <string>

#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"
#include "excite/hal/transport.hpp"
#include "firmware/app/gateway_config.hpp"

namespace excite::app {

/// The bus (null on failure), the error "<field> = <value>, expected <what>" when it is
/// null, and the transport's own counts.
using BusResult = hal::MadeBus;

/// `clock` is what the transport measures the age of received values with (a real clock
/// even when the gateway ticks in lockstep); it must outlive the bus. `lockstep` (with a
/// heartbeat_echo value): the transport is told which value carries the peer's echo of the
/// tick's heartbeat, so that each read sees the answer to that tick's write.
BusResult make_field_bus(const GatewayConfig& config, const hal::Clock& clock,
                         bool lockstep = false);

/// "" when every value the gateway writes back (the command register with
/// `acknowledge = "clear"`) is one `bus` can write; else the error naming the value.
std::string check_written_values(const GatewayConfig& config, const hal::FieldBus& bus);

/// "" when one tick's traffic fits the tick (hal::TransportConfig::check_tick), else the
/// transport's reason naming the load.
std::string check_bus_timing(const GatewayConfig& config, double period_s);

/// The transport's own counts for the end-of-run summary; "" for a transport without any.
/// Called after the run (allocates).
std::string bus_counts_report(const BusResult& made);

/// One line naming the peer in its transport's words (hal::TransportConfig::describe_peer).
std::string describe_peer(const GatewayConfig& config);

}  // namespace excite::app
