// SPDX-License-Identifier: MIT
// excite-plant serving Modbus RTU on a serial device: a pseudo-terminal pair made by socat
// (a real serial line's stand-in: termios, framing by silence, CRC), driven by hal's
// ModbusFieldBus in RTU mode — the gateway's own client code. CAN serving is not
// implemented: --can is refused by name (exit 2).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <thread>

#include "hal/modbus/modbus_field_bus.hpp"
#include "plant_runner.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/default_map.hpp"

namespace excite::sim::server {
namespace {

using test::PlantRunner;
using test::TempDir;
using ::testing::HasSubstr;

constexpr const char* kSocat = "/usr/bin/socat";

TEST(ExcitePlantRtu, LockstepOverAPtyPairEqualsThePlantSteppedInProcess) {
  if (!std::filesystem::exists(kSocat)) GTEST_SKIP() << "socat is not installed (Debian: socat)";
  TempDir dir;
  const auto plant_end = dir.path() / "plant-tty";
  const auto gateway_end = dir.path() / "gateway-tty";
  // GIVEN a pty pair (socat) with the plant on one end
  PlantRunner socat(
      kSocat,
      {"pty,raw,echo=0,link=" + plant_end.string(), "pty,raw,echo=0,link=" + gateway_end.string()},
      dir.path() / "socat.txt");
  for (int i = 0;
       i < 100 && !(std::filesystem::exists(plant_end) && std::filesystem::exists(gateway_end));
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(std::filesystem::exists(gateway_end)) << socat.stderr_text();
  PlantRunner plant({"--plant", "woodberry2x2", "--modbus-rtu", plant_end.string(), "--baud",
                     "38400", "--clock", "lockstep"},
                    dir.path() / "plant.txt");
  ASSERT_TRUE(plant.wait_listening()) << plant.first_line() << plant.stderr_text();
  EXPECT_EQ(plant.first_line(), "listening " + plant_end.string() + ":38400");

  // WHEN the gateway's field bus, in RTU mode on the other end, steps it 20 times
  hal::modbus::ModbusConfig bus_config;
  bus_config.device.transport = "rtu";
  bus_config.device.serial_port = gateway_end.string();
  bus_config.device.baud = 38400;
  bus_config.device.response_timeout_ms = 1000;
  bus_config.map = default_registers(2, 2).map;
  hal::modbus::ModbusFieldBus bus;
  const auto v = bus.configure(bus_config);
  ASSERT_TRUE(v.ok()) << v.message();
  const auto reference = make_plant("woodberry2x2");
  reference->reset(1.0);
  double largest = 0.0;
  for (std::uint16_t k = 1; k <= 20; ++k) {
    const std::array<double, 2> u{k % 4 < 2 ? 0.5 : -0.25, k % 6 < 3 ? -0.125 : 0.375};
    std::array<double, 2> y{};
    ASSERT_EQ(bus.exchange(u, k, y), hal::StatusCode::ok) << "k = " << k << ": " << bus.detail();
    // THEN it reads exactly the plant stepped in process (float32 registers, exact inputs)
    std::array<double, 2> dy{};
    reference->step(u, dy);
    for (std::size_t j = 0; j < 2; ++j) {
      EXPECT_EQ(y[j], static_cast<double>(static_cast<float>(dy[j]))) << "k = " << k;
      largest = std::max(largest, std::abs(dy[j]));
    }
  }
  EXPECT_GT(largest, 0.1);  // the plant responded
  ASSERT_EQ(plant.stop(SIGTERM), 0) << plant.stderr_text();
  EXPECT_THAT(plant.stderr_text(), HasSubstr("stopped after 20 samples"));
}

TEST(ExcitePlantRtu, MissingSerialDeviceExitsOneWithTheDeviceNamed) {
  TempDir dir;
  PlantRunner plant({"--plant", "woodberry2x2", "--modbus-rtu", "/nonexistent/tty"},
                    dir.path() / "plant.txt");
  EXPECT_FALSE(plant.wait_listening());
  EXPECT_EQ(plant.wait_exit(), 1);
  EXPECT_THAT(plant.stderr_text(), HasSubstr("cannot open serial device /nonexistent/tty"));
}

TEST(ExcitePlantCan, AnInterfaceItCannotOpenExitsOneNamingIt) {
  // Here either the kernel has no AF_CAN (this build machine) or the interface does not
  // exist; both are named, nothing is served. Serving itself: tests/hil/loop/can_loop_test
  // (label can-vm, in toolchain/can-vm's VM).
  TempDir dir;
  PlantRunner plant({"--plant", "woodberry2x2", "--can", "excite-nocan"}, dir.path() / "plant.txt");
  EXPECT_FALSE(plant.wait_listening());
  EXPECT_EQ(plant.wait_exit(), 1);
  EXPECT_THAT(plant.stderr_text(), HasSubstr("excite-plant: --can = \"excite-nocan\", expected "));
}

TEST(ExcitePlantCan, AnInterfaceNameTooLongIsRefusedByName) {
  TempDir dir;
  PlantRunner plant({"--plant", "woodberry2x2", "--can", "a-name-of-twenty-chars"},
                    dir.path() / "plant.txt");
  EXPECT_FALSE(plant.wait_listening());
  EXPECT_EQ(plant.wait_exit(), 2);
  EXPECT_THAT(plant.stderr_text(),
              HasSubstr("--can = \"a-name-of-twenty-chars\", expected an interface name of "
                        "1..15 characters"));
}

}  // namespace
}  // namespace excite::sim::server
