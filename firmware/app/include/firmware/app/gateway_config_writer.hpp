// SPDX-License-Identifier: MIT
#pragma once
// Writing the gateway configuration: the gateway's own keys, written from the structs its
// reader fills (gateway_config.hpp) and beside that reader, so what is written reads back
// as written. A transport's keys are the transport's to write, and they come in as text:
// its [device] keys (hal/modbus's format_device_keys; CAN has none), its sections
// (format_map_settings, format_can_settings) and each entry's mapping (format_register_entry,
// format_can_entry). `excite loop-config` composes a file from these writers.
// Start-up code (allocates). Numbers and strings are written through base/config/writer.hpp;
// every function returns whole lines.

#include <string>
#include <string_view>

#include "firmware/app/gateway_config.hpp"

namespace excite::app {

/// [gateway]: plant, period_s (when set), comm_fail_limit, comm_loss and realtime_priority
/// always; every other key of the section only where `c` differs from the reader's default.
/// Ends with a blank line.
std::string format_gateway_section(const GatewayConfig& c);

/// [closed_loop]: offsets, controller, controller_timeout_s, and mv_baseline when it is
/// known. Ends with a blank line.
std::string format_closed_loop_section(const ClosedLoopSpec& c);

/// [device]: transport = `transport`, simulator when true, then `transport_keys` (the
/// transport's own [device] keys, as its writer gives them), then peer_watchdog_s when
/// declared. Ends with a blank line.
std::string format_device_section(std::string_view transport, const GatewayConfig& c,
                                  const std::string& transport_keys);

/// One [[setpoints]] entry, starting with a blank line: name, unit, then `mapping` (the
/// transport's keys for its field location), then min, max, max_move and readback (when set).
std::string format_setpoint(const SetpointSpec& s, const std::string& mapping);

/// One [[values]] entry, starting with a blank line: name, unit (not for a code or counter
/// without one: heartbeat_echo, command, controller_mode, mv_status), role (unless output),
/// acknowledge (command: when it clears), then `mapping`, then test_low, test_high and hysteresis
/// when the value has test limits.
std::string format_value(const ValueSpec& v, const std::string& mapping);

}  // namespace excite::app
