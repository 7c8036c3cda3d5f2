// SPDX-License-Identifier: MIT
// The CAN field bus on a real SocketCAN interface (vcan0), with a raw socket as the
// peer. Skips with the reason on kernels without AF_CAN or without vcan0 (fails instead
// inside toolchain/can-vm); the one test that runs there checks the transport reports
// "unavailable" with that reason.
#include <gtest/gtest.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>

#include "excite/hal/virtual_clock.hpp"
#include "hal/can/can_field_bus.hpp"
#include "vcan_required.hpp"

using namespace excite::hal;
using namespace excite::hal::can;

namespace {

constexpr const char* interface_name = "vcan0";

CanConfig tick_config() {
  CanConfig config;
  config.interface = interface_name;
  config.map.setpoints = {CanSignal{"F1", 0x210, false, 0, "int16", "little", 0.1, 0.0},
                          CanSignal{"F2", 0x210, false, 2, "int16", "little", 0.1, 0.0}};
  config.map.heartbeat = CanSignal{"hb", 0x210, false, 4, "uint16", "little", 1.0, 0.0};
  config.map.values = {CanSignal{"T1", 0x310, false, 0, "float32", "little", 1.0, 0.0}};
  config.value_timeout_ms = 100;
  return config;
}

// A raw socket on vcan0 playing the PLC.
class Peer {
 public:
  Peer() {
    fd_ = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(if_nametoindex(interface_name));
    bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address);
  }
  ~Peer() { close(fd_); }
  Peer(const Peer&) = delete;
  Peer& operator=(const Peer&) = delete;

  bool receive(can_frame& frame) {
    pollfd p{fd_, POLLIN, 0};
    return poll(&p, 1, 1000) == 1 &&
           ::read(fd_, &frame, sizeof frame) == static_cast<ssize_t>(sizeof frame);
  }
  void send_value(float value) {
    can_frame frame{};
    frame.can_id = 0x310;
    frame.can_dlc = 4;
    std::memcpy(frame.data, &value, sizeof value);  // little-endian host
    ASSERT_EQ(::write(fd_, &frame, sizeof frame), static_cast<ssize_t>(sizeof frame));
  }

 private:
  int fd_ = -1;
};

}  // namespace

TEST(CanSocket, AKernelWithoutSocketCanIsReportedUnavailableWithTheReason) {
  const SocketCanSupport support = probe_socketcan();
  if (support.status == StatusCode::ok) {
    GTEST_SKIP() << "this kernel has AF_CAN";
  }
  VirtualClock clock;
  CanFieldBus bus(clock);
  const auto v = bus.configure(tick_config());
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "can.interface");
  EXPECT_NE(v.expected.find(support.reason), std::string::npos) << v.message();
  std::array<double, 2> setpoints{};
  EXPECT_EQ(bus.write(setpoints, 0), StatusCode::unavailable);
  EXPECT_STREQ(bus.detail(), support.reason);
}

TEST(CanSocket, WriteSendsTheSetpointFrameThePeerDecodes) {
  EXCITE_REQUIRE_SOCKETCAN(interface_name);
  Peer peer;
  VirtualClock clock;
  CanFieldBus bus(clock);
  ASSERT_TRUE(bus.configure(tick_config()).ok());
  const std::array<double, 2> setpoints{12.3, -4.5};
  ASSERT_EQ(bus.write(setpoints, 0x0102), StatusCode::ok) << bus.detail();
  can_frame frame{};
  ASSERT_TRUE(peer.receive(frame));
  EXPECT_EQ(frame.can_id, 0x210U);
  EXPECT_EQ(frame.can_dlc, 6);
  EXPECT_EQ(frame.data[0], 123);   // 12.3 / 0.1
  EXPECT_EQ(frame.data[2], 0xD3);  // -45 = 0xFFD3
  EXPECT_EQ(frame.data[3], 0xFF);
  EXPECT_EQ(frame.data[4], 0x02);  // heartbeat, little-endian
  EXPECT_EQ(frame.data[5], 0x01);
}

TEST(CanSocket, ReadDecodesTheNewestValueFrame) {
  EXCITE_REQUIRE_SOCKETCAN(interface_name);
  Peer peer;
  VirtualClock clock;
  CanFieldBus bus(clock);
  ASSERT_TRUE(bus.configure(tick_config()).ok());
  std::array<double, 1> values{-1.0};
  EXPECT_EQ(bus.read(values), StatusCode::timeout);  // nothing received yet
  EXPECT_EQ(values[0], -1.0);
  peer.send_value(1.0F);
  peer.send_value(123456.0F);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // let the kernel deliver
  ASSERT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(values[0], 123456.0);
}

TEST(CanSocket, AValueFrameOlderThanTheTimeoutIsStale) {
  EXCITE_REQUIRE_SOCKETCAN(interface_name);
  Peer peer;
  VirtualClock clock;
  CanFieldBus bus(clock);
  ASSERT_TRUE(bus.configure(tick_config()).ok());
  peer.send_value(5.0F);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::array<double, 1> values{};
  ASSERT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
  clock.advance(std::chrono::milliseconds(101));
  EXPECT_EQ(bus.read(values), StatusCode::timeout);
  EXPECT_NE(std::string(bus.detail()).find("stale"), std::string::npos) << bus.detail();
}

TEST(CanSocket, AMissingInterfaceFailsConfigurationNamingIt) {
  EXCITE_REQUIRE_SOCKETCAN(nullptr);
  VirtualClock clock;
  CanFieldBus bus(clock);
  CanConfig config = tick_config();
  config.interface = "excite-nocan";
  const auto v = bus.configure(config);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.value, "\"excite-nocan\"");
  EXPECT_NE(v.expected.find("if_nametoindex"), std::string::npos) << v.message();
}
