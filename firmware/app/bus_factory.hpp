// SPDX-License-Identifier: MIT
#pragma once
// The field bus of the configured transport, built and configured at start-up (allocates,
// connects or opens the socket, writes nothing): Modbus TCP, Modbus RTU or SocketCAN.

#include <memory>
#include <string>

#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"
#include "firmware/app/gateway_config.hpp"
#include "hal/can/can_field_bus.hpp"

namespace excite::app {

struct BusResult {
  std::unique_ptr<hal::FieldBus> bus;          // configured; null on failure
  std::string error;                           // "<field> = <value>: expected <what>" when !bus
  const hal::can::CanFieldBus* can = nullptr;  // `bus` when it is CAN (its counts), else null
};

/// `clock` is what the CAN bus measures the age of value frames with (a real clock even
/// when the gateway ticks in lockstep); it must outlive the bus. `lockstep` (CAN with a
/// heartbeat_echo value): each read waits for the peer's echo of the tick's heartbeat
/// (hal::can::CanConfig::await_echo), so it sees the answer to that tick's write.
BusResult make_field_bus(const GatewayConfig& config, const hal::Clock& clock,
                         bool lockstep = false);

/// CAN with a [can] bitrate: "" when one tick's frames fit the tick at their worst case
/// (hal/can/bus_timing.hpp), else "can.bitrate = ...: expected ..." naming the load. Other
/// transports and a virtual bus (no bitrate): "".
std::string check_bus_timing(const GatewayConfig& config, double period_s);

/// The transport's own counts for the end-of-run summary; "" for a transport without any (Modbus
/// reports through exception_counts()). CAN: "can vcan0: value frames refused for their DLC 40
/// (first 0x300 DLC 2), frames of the gateway's own identifiers from another node 20 (first
/// 0x200), sends refused 0, reads with a value frame stale or missing 0, echoes missing 0, error
/// frames 0". Called after the run (allocates).
std::string bus_counts_report(const BusResult& made);

/// One line naming the peer, e.g. "modbus-tcp 10.0.0.5:502 unit 1, response timeout 200 ms".
std::string describe_peer(const GatewayConfig& config);

}  // namespace excite::app
