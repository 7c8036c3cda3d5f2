// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

namespace excite::hal {

// The one status every hal operation returns. Return contract, for every transport:
//   ok            the whole operation completed; outputs were written (read) in full.
//   timeout       the peer did not answer within its response timeout, or the transmit
//                 queue was full this cycle; outputs untouched; the next call retries
//                 (Modbus reconnects first: a late reply must not be taken for the next).
//   link_lost     the connection dropped (EPIPE, ECONNRESET, EBADF), a reconnect failed,
//                 or the CAN controller is bus-off / ENOBUFS persisted; outputs
//                 untouched; the next call tries to reconnect.
//   peer_error    the peer answered with a Modbus exception or a malformed reply;
//                 outputs untouched; the link is kept.
//   unavailable   the transport cannot work here (not configured, or e.g. a kernel
//                 without AF_CAN); permanent until reconfigured; detail() says why.
//   bad_argument  caller error (wrong span size, NaN setpoint); nothing was sent.
// A write that fails after some of its requests went out leaves those written: the
// protocol has no transaction; the status reports the failure.
enum class Status : std::uint8_t { ok, timeout, link_lost, peer_error, unavailable, bad_argument };

constexpr const char* to_string(Status status) noexcept {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::timeout:
      return "timeout";
    case Status::link_lost:
      return "link_lost";
    case Status::peer_error:
      return "peer_error";
    case Status::unavailable:
      return "unavailable";
    case Status::bad_argument:
      return "bad_argument";
  }
  return "unknown";
}

}  // namespace excite::hal
