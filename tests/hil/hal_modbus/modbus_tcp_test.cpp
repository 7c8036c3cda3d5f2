// SPDX-License-Identifier: MIT
// The Modbus TCP field bus against a real libmodbus server on loopback, with faults on
// purpose: every status of the contract (excite/hal/status.hpp) is provoked once.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include "fault_server.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

using namespace excite::hal;
using namespace excite::hal::modbus;
using excite::test::FaultServer;

namespace {

// 2 float setpoints (CDAB) at 100.., a uint16 setpoint at 104 (0..100 %), heartbeat 105;
// 2 float values (ABCD, input registers) at 200.., an int16 value (holding) at 300.
ModbusConfig tick_config(std::uint16_t port) {
  ModbusConfig config;
  config.device.port = port;
  config.device.response_timeout_ms = 300;  // generous: the machine is shared
  config.map.setpoints = {RegisterEntry{"F1", 100, 16, "float32", "CDAB", 0, 0, {}, {}},
                          RegisterEntry{"F2", 102, 16, "float32", "CDAB", 0, 0, {}, {}},
                          RegisterEntry{"valve", 104, 16, "uint16", "ABCD", 0.0, 100.0, {}, {}}};
  config.map.heartbeat_address = 105;
  config.map.values = {RegisterEntry{"T1", 200, 4, "float32", "ABCD", 0, 0, {}, {}},
                       RegisterEntry{"T2", 202, 4, "float32", "ABCD", 0, 0, {}, {}},
                       RegisterEntry{"dP", 300, 3, "int16", "ABCD", -50.0, 50.0, {}, {}}};
  return config;
}

void serve_values(FaultServer& server) {
  server.set_input(200, 0x47F1);  // 123456.0f, ABCD
  server.set_input(201, 0x2000);
  server.set_input(202, 0xC2F6);  // -123.0f = 0xC2F60000
  server.set_input(203, 0x0000);
  server.set_holding(300, 0x8000);  // int16 -32768 → -50
}

std::uint16_t free_port() {  // a port nothing listens on
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

constexpr std::array<double, 3> setpoints{123456.0, -1.5, 25.0};

}  // namespace

TEST(ModbusTcp, ExchangeWritesSetpointsAndHeartbeatAndReadsValues) {
  FaultServer server;
  serve_values(server);
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  std::array<double, 3> values{};
  ASSERT_EQ(bus.exchange(setpoints, 7, values), StatusCode::ok) << bus.detail();

  EXPECT_EQ(server.holding(100), 0x2000);  // 123456.0f in CDAB
  EXPECT_EQ(server.holding(101), 0x47F1);
  EXPECT_EQ(server.holding(102), 0x0000);  // -1.5f = 0xBFC00000 in CDAB
  EXPECT_EQ(server.holding(103), 0xBFC0);
  EXPECT_EQ(server.holding(104), 16384);  // 25 % of 0..65535, rounded
  EXPECT_EQ(server.holding(105), 7);      // heartbeat
  EXPECT_EQ(values[0], 123456.0);
  EXPECT_EQ(values[1], -123.0);
  EXPECT_EQ(values[2], -50.0);
  EXPECT_STREQ(bus.detail(), "");
}

TEST(ModbusTcp, OneTickIsOneWriteAndOneReadPerRegisterTable) {
  FaultServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  std::array<double, 3> values{};
  ASSERT_EQ(bus.exchange(setpoints, 1, values), StatusCode::ok) << bus.detail();
  const auto seen = server.seen();
  ASSERT_EQ(seen.size(), 3U);  // FC16 100..105, FC03 300, FC04 200..203
  EXPECT_EQ(seen[0].function_code, 16);
  EXPECT_EQ(seen[0].address, 100);
  EXPECT_EQ(seen[0].count, 6);
  EXPECT_EQ(server.count(3), 1);
  EXPECT_EQ(server.count(4), 1);
}

TEST(ModbusTcp, AMapOf300RegistersTakesThreeRequestsEachWayOnTheServer) {
  FaultServer server;
  ModbusConfig config;
  config.device.port = server.port();
  for (std::uint32_t i = 0; i < 300; ++i) {
    config.map.setpoints.push_back(
        RegisterEntry{"s", 1000 + i, 16, "uint16", "ABCD", 0.0, 65535.0, {}, {}});
    config.map.values.push_back(
        RegisterEntry{"v", 1000 + i, 3, "uint16", "ABCD", 0.0, 65535.0, {}, {}});
  }
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(config).ok());
  std::vector<double> out(300);
  std::vector<double> in(300, 0.0);
  for (std::size_t i = 0; i < 300; ++i) {
    out[i] = static_cast<double>(i * 200);
  }
  ASSERT_EQ(bus.exchange(out, 0, in), StatusCode::ok) << bus.detail();
  const auto seen = server.seen();
  ASSERT_EQ(seen.size(), 6U);
  EXPECT_EQ(server.count(16), 3);
  EXPECT_EQ(server.count(3), 3);
  EXPECT_EQ(seen[0].count, 123);
  EXPECT_EQ(seen[1].count, 123);
  EXPECT_EQ(seen[2].count, 54);
  EXPECT_EQ(seen[2].address, 1246);
  EXPECT_EQ(seen[3].count, 125);
  EXPECT_EQ(seen[4].count, 125);
  EXPECT_EQ(seen[5].count, 50);
  EXPECT_EQ(in, out);  // what was written to holding registers reads back
}

TEST(ModbusTcp, AStalledPeerGivesTimeoutThenTheClientReconnects) {
  FaultServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  std::array<double, 3> values{};
  server.inject(FaultServer::Fault::stall, 1, std::chrono::milliseconds(600));
  EXPECT_EQ(bus.exchange(setpoints, 1, values), StatusCode::timeout);
  EXPECT_NE(std::string(bus.detail()).find("timed out"), std::string::npos) << bus.detail();
  EXPECT_FALSE(bus.connected());
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // the stall ends
  EXPECT_EQ(bus.exchange(setpoints, 2, values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(bus.reconnects(), 1U);
  EXPECT_EQ(server.holding(105), 2);
}

TEST(ModbusTcp, ADroppedConnectionGivesLinkLostThenTheClientReconnects) {
  FaultServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  std::array<double, 3> values{};
  server.inject(FaultServer::Fault::drop);
  EXPECT_EQ(bus.exchange(setpoints, 1, values), StatusCode::link_lost);
  EXPECT_NE(std::string(bus.detail()).find("write FC16 address 100 count 6"), std::string::npos)
      << bus.detail();
  EXPECT_EQ(bus.exchange(setpoints, 2, values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(bus.reconnects(), 1U);
}

TEST(ModbusTcp, AnExceptionReplyGivesPeerErrorKeepsTheLinkAndLeavesValuesUntouched) {
  FaultServer server;
  serve_values(server);
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  ASSERT_TRUE(bus.write(setpoints, 1) == StatusCode::ok);
  std::array<double, 3> values{-1.0, -1.0, -1.0};
  server.inject(FaultServer::Fault::exception);
  EXPECT_EQ(bus.read(values), StatusCode::peer_error);
  EXPECT_NE(std::string(bus.detail()).find("failure"), std::string::npos) << bus.detail();
  EXPECT_EQ(values, (std::array<double, 3>{-1.0, -1.0, -1.0}));
  EXPECT_TRUE(bus.connected());
  EXPECT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(values[0], 123456.0);
  EXPECT_EQ(bus.reconnects(), 0U);
}

// A transient exception (4) is no refusal; exception 3 to a write is, worded by the bus: the
// request, the reason, and the setpoints whose registers it carried (all three: one FC16 of
// registers 100..105). The next good call clears it.
TEST(ModbusTcp, AnIllegalDataValueIsARefusalNamingTheRequestAndItsSetpoints) {
  FaultServer server;
  serve_values(server);
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  server.inject(FaultServer::Fault::exception);
  EXPECT_EQ(bus.write(setpoints, 1), StatusCode::peer_error);
  EXPECT_FALSE(bus.last_refusal().valid);
  server.inject(FaultServer::Fault::refusal);
  EXPECT_EQ(bus.write(setpoints, 2), StatusCode::peer_error);
  const PeerRefusal refused = bus.last_refusal();
  ASSERT_TRUE(refused.valid);
  EXPECT_TRUE(refused.write);
  EXPECT_EQ(refused.setpoints, 0b111U);
  EXPECT_STREQ(refused.request.data(), "FC16 registers 100..105");
  EXPECT_STREQ(refused.reason.data(), "exception 3, illegal data value — the device's own limits?");
  EXPECT_EQ(bus.exception_counts()[3], 1U);
  EXPECT_EQ(bus.exception_counts()[4], 1U);
  std::array<double, 3> values{};
  server.inject(FaultServer::Fault::refusal);
  EXPECT_EQ(bus.read(values), StatusCode::peer_error);
  EXPECT_FALSE(bus.last_refusal().write);
  EXPECT_EQ(bus.last_refusal().setpoints, 0U);
  // The first read request is the holding register's.
  EXPECT_STREQ(bus.last_refusal().request.data(), "FC03 registers 300..300");
  EXPECT_EQ(bus.read(values), StatusCode::ok) << bus.detail();
  EXPECT_FALSE(bus.last_refusal().valid);
}

TEST(ModbusTcp, APeerThatIsGoneGivesLinkLostUntilItComesBack) {
  auto server = std::make_unique<FaultServer>();
  const std::uint16_t port = server->port();
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(port)).ok());
  std::array<double, 3> values{};
  server->stop();
  EXPECT_EQ(bus.exchange(setpoints, 1, values), StatusCode::link_lost);
  EXPECT_EQ(bus.exchange(setpoints, 2, values), StatusCode::link_lost);  // reconnect refused
  EXPECT_NE(std::string(bus.detail()).find("reconnect failed"), std::string::npos) << bus.detail();
  server = std::make_unique<FaultServer>(port);
  EXPECT_EQ(bus.exchange(setpoints, 3, values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(server->holding(105), 3);
}

TEST(ModbusTcp, AnUnreachableDeviceFailsConfigurationNamingIt) {
  ModbusFieldBus bus;
  const std::uint16_t port = free_port();
  const auto v = bus.configure(tick_config(port));
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "device.host");
  EXPECT_EQ(v.value, "tcp 127.0.0.1:" + std::to_string(port) + " unit 1");
  EXPECT_NE(v.expected.find("Connection refused"), std::string::npos) << v.message();
}

TEST(ModbusTcp, BadSetpointsSendNothing) {
  FaultServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  const std::array<double, 3> not_a_number{1.0, std::nan(""), 2.0};
  EXPECT_EQ(bus.write(not_a_number, 1), StatusCode::bad_argument);
  EXPECT_NE(std::string(bus.detail()).find("setpoints[1]"), std::string::npos) << bus.detail();
  const std::array<double, 2> too_few{1.0, 2.0};
  EXPECT_EQ(bus.write(too_few, 1), StatusCode::bad_argument);
  EXPECT_TRUE(server.seen().empty());
}

TEST(ModbusTcp, OutOfRangeScaledSetpointsAreClampedAndCounted) {
  FaultServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(tick_config(server.port())).ok());
  const std::array<double, 3> too_open{0.0, 0.0, 140.0};
  ASSERT_EQ(bus.write(too_open, 1), StatusCode::ok) << bus.detail();
  EXPECT_EQ(server.holding(104), 65535);
  EXPECT_EQ(bus.clamped_setpoints(), 1U);
}
