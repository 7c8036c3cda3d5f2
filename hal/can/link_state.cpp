// SPDX-License-Identifier: MIT
#include "hal/can/link_state.hpp"

#include <linux/can/error.h>

#include <cerrno>

namespace excite::hal::can {

void LinkState::on_error_frame(const can_frame& frame) noexcept {
  if ((frame.can_id & CAN_ERR_FLAG) == 0) {
    return;
  }
  ++error_frames_;
  if ((frame.can_id & CAN_ERR_BUSOFF) != 0) {
    bus_off_ = true;
  }
  if ((frame.can_id & CAN_ERR_RESTARTED) != 0) {
    bus_off_ = false;
  }
}

StatusCode LinkState::on_write(int error) noexcept {
  if (error == 0) {
    enobufs_streak_ = 0;
    return bus_off_ ? StatusCode::link_lost : StatusCode::ok;
  }
  if (error == ENOBUFS || error == EAGAIN) {
    if (enobufs_streak_ < enobufs_limit_) {
      ++enobufs_streak_;
    }
    return lost() ? StatusCode::link_lost : StatusCode::timeout;
  }
  return StatusCode::link_lost;  // ENETDOWN (interface down), EBADF, …
}

}  // namespace excite::hal::can
