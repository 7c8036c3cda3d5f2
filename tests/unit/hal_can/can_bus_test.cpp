// SPDX-License-Identifier: MIT
// The CAN field bus's cyclic logic over the seam below the socket: a
// socketpair(AF_UNIX, SOCK_SEQPACKET) carries struct can_frame datagrams between the bus
// and a peer playing the PLC and the controller. Runs on any kernel (no AF_CAN needed);
// the SocketCAN set-up itself is tested on vcan in tests/hil/hal_can.
#include <gtest/gtest.h>
#include <linux/can/error.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "excite/hal/virtual_clock.hpp"
#include "hal/can/can_field_bus.hpp"

using namespace excite::hal;
using namespace excite::hal::can;

namespace {

// Setpoints: 0x210 (two int16, heartbeat uint16), extended 0x18FF0001 (float32).
// Values: 0x310 (float32), 0x311 (int16, 0.01 units/count).
CanConfig config() {
  CanConfig c;
  c.interface = "pair";
  c.map.setpoints = {CanSignal{"F1", 0x210, false, 0, "int16", "little", 0.1, 0.0},
                     CanSignal{"F2", 0x210, false, 2, "int16", "little", 0.1, 0.0},
                     CanSignal{"Q", 0x18FF0001, true, 0, "float32", "little", 1.0, 0.0}};
  c.map.heartbeat = CanSignal{"hb", 0x210, false, 4, "uint16", "little", 1.0, 0.0};
  c.map.values = {CanSignal{"T1", 0x310, false, 0, "float32", "little", 1.0, 0.0},
                  CanSignal{"dP", 0x311, false, 0, "int16", "little", 0.01, 0.0}};
  c.value_timeout_ms = 100;
  c.enobufs_limit = 3;
  return c;
}

class CanBus : public ::testing::Test {
 protected:
  void SetUp() override {
    int fds[2];
    ASSERT_EQ(socketpair(AF_UNIX, SOCK_SEQPACKET, 0, fds), 0);
    peer_ = fds[1];
    const auto v = bus_.configure_on_socket(config(), fds[0]);
    ASSERT_TRUE(v.ok()) << v.message();
  }
  void TearDown() override { close(peer_); }

  void peer_send(canid_t id, std::uint8_t dlc, const void* data, std::size_t size) {
    can_frame frame{};
    frame.can_id = id;
    frame.can_dlc = dlc;
    std::memcpy(frame.data, data, size);
    ASSERT_EQ(send(peer_, &frame, sizeof frame, 0), static_cast<ssize_t>(sizeof frame));
  }
  void send_t1(float value) { peer_send(0x310, 4, &value, sizeof value); }
  void send_dp(std::int16_t raw) { peer_send(0x311, 2, &raw, sizeof raw); }
  void send_error(canid_t classes) {
    const std::array<std::uint8_t, CAN_ERR_DLC> data{};
    peer_send(CAN_ERR_FLAG | classes, CAN_ERR_DLC, data.data(), data.size());
  }
  bool peer_receive(can_frame& frame) {
    pollfd p{peer_, POLLIN, 0};
    return poll(&p, 1, 0) == 1 &&
           recv(peer_, &frame, sizeof frame, 0) == static_cast<ssize_t>(sizeof frame);
  }

  VirtualClock clock_;
  CanFieldBus bus_{clock_};
  int peer_ = -1;
};

constexpr std::array<double, 3> setpoints{12.3, -4.5, 123456.0};

}  // namespace

TEST_F(CanBus, WriteSendsOneFramePerSetpointIdentifier) {
  ASSERT_EQ(bus_.write(setpoints, 0x0102), StatusCode::ok) << bus_.detail();
  can_frame frame{};
  ASSERT_TRUE(peer_receive(frame));
  EXPECT_EQ(frame.can_id, 0x210U);
  EXPECT_EQ(frame.can_dlc, 6);
  EXPECT_EQ(frame.data[0], 123);   // 12.3 / 0.1
  EXPECT_EQ(frame.data[2], 0xD3);  // -45 = 0xFFD3
  EXPECT_EQ(frame.data[3], 0xFF);
  EXPECT_EQ(frame.data[4], 0x02);  // heartbeat 0x0102, little-endian
  EXPECT_EQ(frame.data[5], 0x01);
  ASSERT_TRUE(peer_receive(frame));
  EXPECT_EQ(frame.can_id, 0x18FF0001U | CAN_EFF_FLAG);
  EXPECT_EQ(frame.data[3], 0x47);  // 123456.0f = 0x47F12000, little-endian
  EXPECT_FALSE(peer_receive(frame));
}

TEST_F(CanBus, BadSetpointsSendNothing) {
  const std::array<double, 3> bad{1.0, std::nan(""), 2.0};
  EXPECT_EQ(bus_.write(bad, 0), StatusCode::bad_argument);
  can_frame frame{};
  EXPECT_FALSE(peer_receive(frame));
}

TEST_F(CanBus, ReadTakesTheNewestFrameOfEachIdentifier) {
  send_t1(1.0F);
  send_dp(-250);
  peer_send(0x312, 2, "xx", 2);  // not mapped: ignored
  send_t1(123456.0F);
  std::array<double, 2> values{};
  ASSERT_EQ(bus_.read(values), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(values[0], 123456.0);
  EXPECT_DOUBLE_EQ(values[1], -2.5);
}

TEST_F(CanBus, ReadTimesOutUntilEveryValueFrameHasArrived) {
  send_t1(5.0F);
  std::array<double, 2> values{-1.0, -1.0};
  EXPECT_EQ(bus_.read(values), StatusCode::timeout);
  EXPECT_NE(std::string(bus_.detail()).find("0x311 never received"), std::string::npos)
      << bus_.detail();
  EXPECT_EQ(values, (std::array<double, 2>{-1.0, -1.0}));
  send_dp(1);
  EXPECT_EQ(bus_.read(values), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(values[0], 5.0);
}

TEST_F(CanBus, AValueFrameOlderThanTheTimeoutIsStale) {
  send_t1(5.0F);
  send_dp(1);
  std::array<double, 2> values{};
  ASSERT_EQ(bus_.read(values), StatusCode::ok) << bus_.detail();
  clock_.advance(std::chrono::milliseconds(100));
  EXPECT_EQ(bus_.read(values), StatusCode::ok);  // exactly the timeout: still fresh
  clock_.advance(std::chrono::milliseconds(1));
  EXPECT_EQ(bus_.read(values), StatusCode::timeout);
  EXPECT_NE(std::string(bus_.detail()).find("stale"), std::string::npos) << bus_.detail();
  send_t1(6.0F);
  send_dp(2);
  EXPECT_EQ(bus_.read(values), StatusCode::ok);
  EXPECT_EQ(values[0], 6.0);
}

TEST_F(CanBus, BusOffIsLinkLossUntilTheControllerRestarts) {
  send_t1(5.0F);
  send_dp(1);
  send_error(CAN_ERR_BUSOFF);
  std::array<double, 2> values{};
  EXPECT_EQ(bus_.read(values), StatusCode::link_lost);
  EXPECT_NE(std::string(bus_.detail()).find("bus-off"), std::string::npos) << bus_.detail();
  EXPECT_EQ(bus_.write(setpoints, 1), StatusCode::link_lost);
  send_error(CAN_ERR_RESTARTED);
  EXPECT_EQ(bus_.read(values), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(bus_.write(setpoints, 2), StatusCode::ok) << bus_.detail();
  EXPECT_EQ(bus_.link().error_frames(), 2U);
}

TEST_F(CanBus, AShortValueFrameIsCountedAndIgnored) {
  send_t1(5.0F);
  send_dp(1);
  std::array<double, 2> values{};
  ASSERT_EQ(bus_.read(values), StatusCode::ok);
  peer_send(0x310, 2, "ab", 2);  // float32 needs 4 bytes
  ASSERT_EQ(bus_.read(values), StatusCode::ok);
  EXPECT_EQ(values[0], 5.0);
  EXPECT_EQ(bus_.short_frames(), 1U);
}

// GIVEN a third node on the bus WHEN it sends a short value frame, frames of the gateway's own
// setpoint identifiers (standard and extended) and one nobody maps THEN the short frame is
// refused, the own-identifier frames counted (the first named), the unmapped one ignored; a
// read with a value frame gone stale is counted too.
TEST_F(CanBus, RefusedAndForeignFramesAndStaleReadsAreCounted) {
  send_t1(5.0F);
  send_dp(1);
  std::array<double, 2> values{};
  ASSERT_EQ(bus_.read(values), StatusCode::ok);
  peer_send(0x311, 1, "a", 1);  // int16 needs 2 bytes
  peer_send(0x210, 6, "abcdef", 6);
  peer_send(0x18FF0001 | CAN_EFF_FLAG, 4, "abcd", 4);
  peer_send(0x123, 2, "ab", 2);
  ASSERT_EQ(bus_.read(values), StatusCode::ok);
  EXPECT_EQ(values[1], 0.01);
  CanCounters c = bus_.counters();
  EXPECT_EQ(c.short_frames, 1U);
  EXPECT_EQ(c.first_short_id, 0x311U);
  EXPECT_EQ(c.first_short_dlc, 1U);
  EXPECT_EQ(c.own_id_frames, 2U);
  EXPECT_EQ(c.first_own_id, 0x210U);
  EXPECT_EQ(c.stale_reads, 0U);
  clock_.advance(std::chrono::milliseconds(101));
  EXPECT_EQ(bus_.read(values), StatusCode::timeout);
  EXPECT_EQ(bus_.counters().stale_reads, 1U);
}

TEST_F(CanBus, AFullTransmitQueueIsATimeoutAndPersistentlyFullIsLinkLoss) {
  // GIVEN a peer that stops reading, WHEN the bus keeps writing, THEN the queue fills:
  // the first refused write is a timeout, the third in a row (enobufs_limit) link loss.
  StatusCode status = StatusCode::ok;
  int writes = 0;
  while (status == StatusCode::ok && writes < 100000) {
    status = bus_.write(setpoints, 0);
    ++writes;
  }
  ASSERT_EQ(status, StatusCode::timeout) << bus_.detail();
  EXPECT_EQ(bus_.write(setpoints, 0), StatusCode::timeout);
  EXPECT_EQ(bus_.write(setpoints, 0), StatusCode::link_lost);
  EXPECT_EQ(bus_.counters().send_failures, 3U);  // the summary's "sends refused"
  EXPECT_NE(bus_.counters().last_send_error, 0);
  // WHEN the peer drains the queue THEN writing works again.
  can_frame frame{};
  while (peer_receive(frame)) {
  }
  EXPECT_EQ(bus_.write(setpoints, 0), StatusCode::ok) << bus_.detail();
}

// ---- waiting for the peer: the first read, and lock-step (CanConfig::await_echo) ----

namespace {

// A bus on one end of a socketpair with the map of config() plus a heartbeat echo value
// (0x313, uint16) when `echo`; the other end is returned in `peer`.
void open_pair(CanFieldBus& bus, int& peer, bool echo) {
  int fds[2];
  ASSERT_EQ(socketpair(AF_UNIX, SOCK_SEQPACKET, 0, fds), 0);
  CanConfig c = config();
  if (echo) {
    c.map.values.push_back(CanSignal{"hb_echo", 0x313, false, 0, "uint16", "little", 1.0, 0.0});
    c.await_echo = 2;
  }
  const auto v = bus.configure_on_socket(c, fds[0]);
  ASSERT_TRUE(v.ok()) << v.message();
  peer = fds[1];
}

// The peer's answer: T1 = t1, dP = 0.01, and (after them) the echo of `heartbeat`.
void answer(int peer, float t1, std::uint16_t heartbeat) {
  can_frame f{};
  f.can_id = 0x310;
  f.can_dlc = 4;
  std::memcpy(f.data, &t1, 4);
  ASSERT_EQ(send(peer, &f, sizeof f, 0), static_cast<ssize_t>(sizeof f));
  f = can_frame{};
  f.can_id = 0x311;
  f.can_dlc = 2;
  f.data[0] = 1;
  ASSERT_EQ(send(peer, &f, sizeof f, 0), static_cast<ssize_t>(sizeof f));
  f = can_frame{};
  f.can_id = 0x313;
  f.can_dlc = 2;
  std::memcpy(f.data, &heartbeat, 2);
  ASSERT_EQ(send(peer, &f, sizeof f, 0), static_cast<ssize_t>(sizeof f));
}

}  // namespace

TEST(CanBusWaits, TheFirstReadWaitsForValueFramesSentOnThePeersOwnCycle) {
  VirtualClock clock;
  CanFieldBus bus(clock);
  int peer = -1;
  open_pair(bus, peer, false);
  std::thread later([peer] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    answer(peer, 4.0F, 0);  // 0x313 is not mapped here: ignored
  });
  std::array<double, 2> values{};
  EXPECT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(values[0], 4.0);
  later.join();
  close(peer);
}

TEST(CanBusWaits, WithAwaitEchoAReadReturnsThePeersAnswerToThatWrite) {
  for (const bool echo : {false, true}) {
    VirtualClock clock;
    CanFieldBus bus(clock);
    int peer = -1;
    open_pair(bus, peer, echo);
    answer(peer, 1.0F, 6);  // the answer to the previous tick
    ASSERT_EQ(bus.write(setpoints, 7), StatusCode::ok);
    std::thread later([peer] {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      answer(peer, 2.0F, 7);  // the answer to this one, after a while
    });
    std::vector<double> values(echo ? 3 : 2);
    EXPECT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
    // Without the echo the read takes what is queued: the previous answer.
    EXPECT_EQ(values[0], echo ? 2.0 : 1.0) << (echo ? "await_echo" : "no await");
    later.join();
    close(peer);
  }
}

TEST(CanBusWaits, NoEchoOfTheHeartbeatWithinTheValueTimeoutIsATimeoutNamingIt) {
  VirtualClock clock;
  CanFieldBus bus(clock);
  int peer = -1;
  open_pair(bus, peer, true);
  answer(peer, 1.0F, 6);
  ASSERT_EQ(bus.write(setpoints, 8), StatusCode::ok);
  std::vector<double> values(3, -1.0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(bus.read(values), StatusCode::timeout);
  EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
  EXPECT_STREQ(bus.detail(), "pair: no echo of heartbeat 8 within 100 ms");
  EXPECT_EQ(values[0], -1.0) << "values untouched";
  close(peer);
}
