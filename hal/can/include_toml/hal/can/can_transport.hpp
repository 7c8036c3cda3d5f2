// SPDX-License-Identifier: MIT
#pragma once
// SocketCAN behind the transport seam (excite/hal/transport.hpp): the [can] section
// (interface, value_timeout_ms, enobufs_limit, bitrate, heartbeat_*), each entry's frame
// layout (can_id, extended, byte_offset, type, byte_order, scale, offset), the signals'
// carried ranges, the tick's bus load (bus_timing.hpp), the words the gateway describes the
// interface and its frames with, and the end-of-run counts (CanCounters).
// Start-up code (library excite_hal_can_toml: reads through base/config and throws).
// The writer sits beside the reader (format_can_settings, format_can_entry: `excite
// loop-config --transport can`), so what is written is what the reader reads back.

#include <memory>
#include <string>

#include "excite/hal/transport.hpp"
#include "hal/can/can_field_bus.hpp"

namespace excite::hal::can {

/// A CAN transport's configuration as the gateway's file gives it ([device] transport "can").
std::unique_ptr<TransportConfig> make_transport_config();

/// The interface and frame map `transport` read, or null when it is not the CAN transport.
const CanConfig* can_config_of(const TransportConfig& transport) noexcept;

/// The [can] section's lines ("key = value\n" each) that the transport reads back into the
/// same fields of `c`: interface, value_timeout_ms, enobufs_limit; bitrate when set;
/// heartbeat_id, _extended (when set), _byte_offset, _type, _byte_order when c.map has a
/// heartbeat. The frame map's entries are their owners' (format_can_entry).
std::string format_can_settings(const CanConfig& c);

/// The frame-layout fields of `s` as TOML lines that the transport's entry reader reads back
/// into the same fields: can_id (hexadecimal), extended (when set), byte_offset, type,
/// byte_order; scale and offset when not 1 and 0. The name is its owner's to write.
std::string format_can_entry(const CanSignal& s);

}  // namespace excite::hal::can
