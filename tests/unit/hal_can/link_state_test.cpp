// SPDX-License-Identifier: MIT
// CAN link health from error frames and transmit results.
#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <cerrno>

#include "hal/can/link_state.hpp"

using excite::hal::StatusCode;
using excite::hal::can::LinkState;

namespace {
can_frame error_frame(canid_t classes) {
  can_frame frame{};
  frame.can_id = CAN_ERR_FLAG | classes;
  frame.can_dlc = CAN_ERR_DLC;
  return frame;
}
}  // namespace

TEST(CanLinkState, BusOffIsLinkLossUntilTheControllerRestarts) {
  LinkState link;
  link.on_error_frame(error_frame(CAN_ERR_BUSOFF));
  EXPECT_TRUE(link.lost());
  EXPECT_EQ(link.on_write(0), StatusCode::link_lost);
  link.on_error_frame(error_frame(CAN_ERR_RESTARTED));
  EXPECT_FALSE(link.lost());
  EXPECT_EQ(link.on_write(0), StatusCode::ok);
  EXPECT_EQ(link.error_frames(), 2U);
}

TEST(CanLinkState, OtherErrorClassesAreCountedButKeepTheLink) {
  LinkState link;
  link.on_error_frame(error_frame(CAN_ERR_CRTL | CAN_ERR_ACK));
  EXPECT_FALSE(link.lost());
  EXPECT_EQ(link.error_frames(), 1U);
}

TEST(CanLinkState, DataFramesAreNotErrorFrames) {
  LinkState link;
  can_frame frame{};
  frame.can_id = CAN_ERR_BUSOFF;  // same bit, but no CAN_ERR_FLAG: an ordinary identifier
  link.on_error_frame(frame);
  EXPECT_FALSE(link.bus_off());
  EXPECT_EQ(link.error_frames(), 0U);
}

TEST(CanLinkState, OneEnobufsIsATimeoutAPersistentOneIsLinkLoss) {
  LinkState link(3);
  EXPECT_EQ(link.on_write(ENOBUFS), StatusCode::timeout);
  EXPECT_EQ(link.on_write(ENOBUFS), StatusCode::timeout);
  EXPECT_EQ(link.on_write(ENOBUFS), StatusCode::link_lost);
  EXPECT_EQ(link.on_write(ENOBUFS), StatusCode::link_lost);
  EXPECT_EQ(link.on_write(0), StatusCode::ok);  // a frame got through: the streak resets
  EXPECT_EQ(link.on_write(ENOBUFS), StatusCode::timeout);
}

TEST(CanLinkState, AnInterfaceDownIsLinkLoss) {
  LinkState link;
  EXPECT_EQ(link.on_write(ENETDOWN), StatusCode::link_lost);
}
