// SPDX-License-Identifier: MIT
// Device configuration, TCP and RTU, checked without a peer; and configure() on a
// device that does not exist (no serial port, nothing listening).
#include <gtest/gtest.h>

#include <string>

#include "hal/modbus/modbus_field_bus.hpp"

using namespace excite::hal;
using namespace excite::hal::modbus;

namespace {
ModbusConfig rtu_config() {
  ModbusConfig config;
  config.device.transport = "rtu";
  config.device.serial_port = "/dev/ttyUSB0";
  config.map.values.push_back(RegisterEntry{"T1", 0, 4, "float32", "CDAB", 0.0, 0.0, {}, {}});
  return config;
}
}  // namespace

TEST(ModbusConfig, AValidRtuConfigurationPasses) {
  EXPECT_TRUE(validate(rtu_config()).ok());
}

TEST(ModbusConfig, RejectsAnUnknownTransport) {
  ModbusConfig config = rtu_config();
  config.device.transport = "udp";
  EXPECT_EQ(validate(config).message(), "device.transport = \"udp\", expected \"tcp\" or \"rtu\"");
}

TEST(ModbusConfig, RtuRejectsBadParityDataBitsStopBitsAndBroadcastSlave) {
  ModbusConfig config = rtu_config();
  config.device.parity = "X";
  EXPECT_EQ(validate(config).field, "device.parity");
  config = rtu_config();
  config.device.data_bits = 9;
  EXPECT_EQ(validate(config).field, "device.data_bits");
  config = rtu_config();
  config.device.stop_bits = 3;
  EXPECT_EQ(validate(config).field, "device.stop_bits");
  config = rtu_config();
  config.device.unit_id = 0;
  EXPECT_EQ(validate(config).field, "device.unit_id");
  config = rtu_config();
  config.device.serial_port.clear();
  EXPECT_EQ(validate(config).field, "device.serial_port");
}

TEST(ModbusConfig, RejectsAResponseTimeoutOutOfRange) {
  ModbusConfig config = rtu_config();
  config.device.response_timeout_ms = 0;
  EXPECT_EQ(validate(config).message(), "device.response_timeout_ms = 0, expected 1..60000 ms");
}

TEST(ModbusConfig, TcpRejectsPortZeroAndUnitIdAbove255) {
  ModbusConfig config;
  config.device.port = 0;
  EXPECT_EQ(validate(config).field, "device.port");
  config.device.port = 502;
  config.device.unit_id = 256;
  EXPECT_EQ(validate(config).field, "device.unit_id");
}

TEST(ModbusConfig, MapErrorsComeThroughValidate) {
  ModbusConfig config = rtu_config();
  config.map.values[0].word_order = "XYZW";
  EXPECT_EQ(validate(config).field, "values[0].word_order");
}

TEST(ModbusConfig, ConfigureFailsOnAMissingSerialPortNamingIt) {
  ModbusConfig config = rtu_config();
  config.device.serial_port = "/dev/excite-no-such-tty";
  ModbusFieldBus bus;
  const auto v = bus.configure(config);
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.field, "device.serial_port");
  EXPECT_NE(v.value.find("/dev/excite-no-such-tty"), std::string::npos) << v.message();
  EXPECT_NE(v.expected.find("connect failed"), std::string::npos) << v.message();
}

TEST(ModbusConfig, AnUnconfiguredBusReportsUnavailable) {
  ModbusFieldBus bus;
  double value = 0.0;
  EXPECT_EQ(bus.read(std::span<double>(&value, 0)), StatusCode::unavailable);
  EXPECT_STREQ(bus.detail(), "not configured");
}
