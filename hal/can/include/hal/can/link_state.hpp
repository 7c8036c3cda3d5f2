// SPDX-License-Identifier: MIT
#pragma once

#include <linux/can.h>

#include <cstdint>

#include "excite/hal/status.hpp"

namespace excite::hal::can {

// What the CAN link's health is, from error frames and transmit results (pure; the
// socket transport feeds it). Link loss, per the status contract:
//   - an error frame with CAN_ERR_BUSOFF: the controller left the bus; lost until an
//     error frame with CAN_ERR_RESTARTED says the controller is back;
//   - ENOBUFS (transmit queue full, typically no ACK from any node) on `enobufs_limit`
//     consecutive write() calls; one such write is a timeout, a successful one resets.
class LinkState {
 public:
  explicit LinkState(std::uint32_t enobufs_limit = 10) noexcept : enobufs_limit_(enobufs_limit) {}

  // Feeds a received error frame (can_id has CAN_ERR_FLAG); other frames are ignored.
  void on_error_frame(const can_frame& frame) noexcept;

  // Result of one write() call's sends: 0 if every frame was queued, else the errno of
  // the first failure. Returns the status that call reports.
  StatusCode on_write(int error) noexcept;

  [[nodiscard]] bool bus_off() const noexcept { return bus_off_; }
  [[nodiscard]] bool lost() const noexcept { return bus_off_ || enobufs_streak_ >= enobufs_limit_; }
  [[nodiscard]] std::uint64_t error_frames() const noexcept { return error_frames_; }
  [[nodiscard]] std::uint32_t enobufs_streak() const noexcept { return enobufs_streak_; }

 private:
  std::uint32_t enobufs_limit_;
  std::uint32_t enobufs_streak_ = 0;
  bool bus_off_ = false;
  std::uint64_t error_frames_ = 0;
};

}  // namespace excite::hal::can
