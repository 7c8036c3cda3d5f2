// SPDX-License-Identifier: MIT
#pragma once
// SocketCAN behind the transport seam (excite/hal/transport.hpp): the [can] section
// (interface, value_timeout_ms, enobufs_limit, bitrate, heartbeat_*), each entry's frame
// layout (can_id, extended, byte_offset, type, byte_order, scale, offset), the signals'
// carried ranges, the tick's bus load (bus_timing.hpp), the words the gateway describes the
// interface and its frames with, and the end-of-run counts (CanCounters).
// Start-up code (library excite_hal_can_toml: reads through base/config and throws).

#include <memory>

#include "excite/hal/transport.hpp"
#include "hal/can/can_field_bus.hpp"

namespace excite::hal::can {

/// A CAN transport's configuration as the gateway's file gives it ([device] transport "can").
std::unique_ptr<TransportConfig> make_transport_config();

/// The interface and frame map `transport` read, or null when it is not the CAN transport.
const CanConfig* can_config_of(const TransportConfig& transport) noexcept;

}  // namespace excite::hal::can
