// SPDX-License-Identifier: MIT
#pragma once

#include "base/status/status.hpp"

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
//
// The codes are the project's one vocabulary (base/status/status.hpp, StatusCode); a hal
// call returns only the six above. Messages (detail(), config::Check) use the one form
// "FIELD = VALUE, expected WHAT".
using excite::StatusCode;
using excite::to_string;

}  // namespace excite::hal
