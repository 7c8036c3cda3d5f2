// SPDX-License-Identifier: MIT
// Modbus RTU without a serial port: a pseudo-terminal pair is the wire. The field bus
// opens the slave side by its path (as it would /dev/ttyUSB0); a libmodbus RTU server
// reads and answers on the master side in a thread.
#include <gtest/gtest.h>
#include <modbus.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>

#include "hal/modbus/modbus_field_bus.hpp"

using namespace excite::hal;
using namespace excite::hal::modbus;

namespace {

constexpr int slave_address = 17;

class RtuPtyServer {
 public:
  RtuPtyServer() {
    std::array<char, 128> name{};
    if (openpty(&master_, &slave_, name.data(), nullptr, nullptr) != 0) {
      ADD_FAILURE() << "openpty failed";
      return;
    }
    termios raw{};
    tcgetattr(slave_, &raw);
    cfmakeraw(&raw);
    tcsetattr(slave_, TCSANOW, &raw);
    path_ = name.data();
    ctx_ = modbus_new_rtu("/dev/null", 19200, 'N', 8, 1);  // the path is never opened
    modbus_set_socket(ctx_, master_);
    modbus_set_slave(ctx_, slave_address);
    mapping_ = modbus_mapping_new(0, 0, 1024, 1024);
    thread_ = std::thread([this] { serve(); });
  }
  ~RtuPtyServer() {
    stopping_ = true;
    if (thread_.joinable()) {
      thread_.join();
    }
    modbus_mapping_free(mapping_);
    modbus_free(ctx_);  // the master fd is ours, not libmodbus's
    close(master_);
    close(slave_);
  }
  RtuPtyServer(const RtuPtyServer&) = delete;
  RtuPtyServer& operator=(const RtuPtyServer&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }
  void set_input(int address, std::uint16_t value) {
    std::lock_guard lock(mutex_);
    mapping_->tab_input_registers[address] = value;
  }
  std::uint16_t holding(int address) {
    std::lock_guard lock(mutex_);
    return mapping_->tab_registers[address];
  }
  void stall_next(std::chrono::milliseconds stall) { stall_ms_ = static_cast<int>(stall.count()); }
  int requests() const { return requests_; }

 private:
  void serve() {
    std::uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
    while (!stopping_) {
      pollfd p{master_, POLLIN, 0};
      if (poll(&p, 1, 20) <= 0 || (p.revents & POLLIN) == 0) {
        continue;
      }
      const int length = modbus_receive(ctx_, query);
      if (length <= 0) {
        continue;  // not for us, or noise: RTU has no connection to lose
      }
      ++requests_;
      if (const int stall = stall_ms_.exchange(0); stall > 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(stall));
        tcflush(master_, TCIFLUSH);
        continue;  // a stalled device never answers this request
      }
      std::lock_guard lock(mutex_);
      modbus_reply(ctx_, query, length, mapping_);
    }
  }

  int master_ = -1;
  int slave_ = -1;  // held open so the master never sees a hang-up between client opens
  std::string path_;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* mapping_ = nullptr;
  std::mutex mutex_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> stall_ms_{0};
  std::atomic<int> requests_{0};
  std::thread thread_;
};

ModbusConfig rtu_config(const std::string& path) {
  ModbusConfig config;
  config.device.transport = "rtu";
  config.device.serial_port = path;
  config.device.baud = 115200;
  config.device.parity = "E";
  config.device.unit_id = slave_address;
  config.device.response_timeout_ms = 300;  // generous: the machine is shared
  config.map.setpoints = {RegisterEntry{"F1", 10, 16, "float32", "DCBA", 0, 0, {}, {}}};
  config.map.heartbeat_address = 12;
  config.map.values = {RegisterEntry{"T1", 20, 4, "float32", "BADC", 0, 0, {}, {}}};
  return config;
}

}  // namespace

TEST(ModbusRtu, ExchangesOverAPseudoTerminalPair) {
  RtuPtyServer server;
  server.set_input(20, 0xF147);  // 123456.0f in BADC
  server.set_input(21, 0x0020);
  ModbusFieldBus bus;
  const auto v = bus.configure(rtu_config(server.path()));
  ASSERT_TRUE(v.ok()) << v.message();
  const std::array<double, 1> setpoints{123456.0};
  std::array<double, 1> values{};
  ASSERT_EQ(bus.exchange(setpoints, 42, values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(server.holding(10), 0x0020);  // DCBA
  EXPECT_EQ(server.holding(11), 0xF147);
  EXPECT_EQ(server.holding(12), 42);
  EXPECT_EQ(values[0], 123456.0);
  EXPECT_EQ(server.requests(), 2);
}

TEST(ModbusRtu, ASilentDeviceTimesOutAndTheNextExchangeSucceeds) {
  RtuPtyServer server;
  ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(rtu_config(server.path())).ok());
  const std::array<double, 1> setpoints{1.0};
  std::array<double, 1> values{};
  server.stall_next(std::chrono::milliseconds(600));
  EXPECT_EQ(bus.exchange(setpoints, 1, values), StatusCode::timeout);
  EXPECT_NE(std::string(bus.detail()).find("rtu " + server.path() + " slave 17"), std::string::npos)
      << bus.detail();
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  EXPECT_EQ(bus.exchange(setpoints, 2, values), StatusCode::ok) << bus.detail();
  EXPECT_EQ(bus.reconnects(), 1U);  // the serial port was reopened
  EXPECT_EQ(server.holding(12), 2);
}
