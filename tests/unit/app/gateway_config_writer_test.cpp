// SPDX-License-Identifier: MIT
// The gateway configuration's writer beside its reader (issue 38 §3): a file composed from
// the writers (the gateway's own keys here, the transport's from hal) reads back into the
// same fields through parse_gateway_config, over Modbus RTU and TCP and over CAN.
#include "firmware/app/gateway_config_writer.hpp"

#include <gtest/gtest.h>

#include <string>

#include "hal/can/can_transport.hpp"
#include "hal/modbus/modbus_transport.hpp"
#include "hal/modbus/register_entry_toml.hpp"

namespace excite::app {
namespace {

GatewayConfig settings() {
  GatewayConfig g;
  g.plant = "column \"C-101\"";
  g.period_s = 0.25;
  g.comm_fail_limit = 5;
  g.comm_loss = engine::CommLossAction::ramp_to_baseline;
  g.realtime_priority = 40;
  g.ramp_s = 30.0;
  g.suspend_timeout_s = 600.0;
  g.confirm_timeout_s = 12.5;
  g.readback_lag_ticks = 2;
  g.log_ring = 8192;
  g.max_distortion = 0.05;
  g.simulator = true;
  g.peer_watchdog_s = 3.0;
  return g;
}

SetpointSpec reflux() {
  SetpointSpec s;
  s.name = "reflux";
  s.unit = "t/h";
  s.min = 9.5;
  s.max = 10.5;
  s.max_move = 0.1;
  s.readback = "reflux_sp";
  return s;
}

std::string values_text(const std::string& output_mapping, const std::string& readback_mapping,
                        const std::string& echo_mapping) {
  ValueSpec y;
  y.name = "xD";
  y.unit = "mol/mol";
  y.test_low = 0.97;
  y.test_high = 0.995;
  y.hysteresis = 0.001;
  ValueSpec rb;
  rb.name = "reflux_sp";
  rb.unit = "t/h";
  rb.role = ValueRole::readback;
  ValueSpec echo;
  echo.name = "hb_echo";
  echo.role = ValueRole::heartbeat_echo;
  return format_value(y, output_mapping) + format_value(rb, readback_mapping) +
         format_value(echo, echo_mapping);
}

void expect_read_back(const GatewayConfig& c) {
  const GatewayConfig g = settings();
  EXPECT_EQ(c.plant, g.plant);
  EXPECT_EQ(c.period_s, g.period_s);
  EXPECT_EQ(c.comm_fail_limit, g.comm_fail_limit);
  EXPECT_EQ(c.comm_loss, g.comm_loss);
  EXPECT_EQ(c.realtime_priority, g.realtime_priority);
  EXPECT_EQ(c.ramp_s, g.ramp_s);
  EXPECT_EQ(c.resume_dwell_s, g.resume_dwell_s);
  EXPECT_EQ(c.suspend_timeout_s, g.suspend_timeout_s);
  EXPECT_EQ(c.confirm_timeout_s, g.confirm_timeout_s);
  EXPECT_EQ(c.readback_lag_ticks, g.readback_lag_ticks);
  EXPECT_EQ(c.log_ring, g.log_ring);
  EXPECT_EQ(c.max_distortion, g.max_distortion);
  EXPECT_EQ(c.simulator, g.simulator);
  EXPECT_EQ(c.peer_watchdog_s, g.peer_watchdog_s);
  ASSERT_EQ(c.setpoints.size(), 1U);
  EXPECT_EQ(c.setpoints[0].name, "reflux");
  EXPECT_EQ(c.setpoints[0].unit, "t/h");
  EXPECT_EQ(c.setpoints[0].min, 9.5);
  EXPECT_EQ(c.setpoints[0].max, 10.5);
  EXPECT_EQ(c.setpoints[0].max_move, 0.1);
  EXPECT_EQ(c.setpoints[0].readback, "reflux_sp");
  ASSERT_EQ(c.values.size(), 3U);
  EXPECT_EQ(c.values[0].unit, "mol/mol");
  EXPECT_EQ(c.values[0].role, ValueRole::output);
  EXPECT_EQ(c.values[0].test_low, 0.97);
  EXPECT_EQ(c.values[0].test_high, 0.995);
  EXPECT_EQ(c.values[0].hysteresis, 0.001);
  EXPECT_EQ(c.values[1].role, ValueRole::readback);
  EXPECT_EQ(c.values[2].role, ValueRole::heartbeat_echo);
  EXPECT_EQ(c.values[2].unit, "-");
}

hal::modbus::RegisterEntry reg(std::uint32_t address, int function_code) {
  hal::modbus::RegisterEntry e;
  e.address = address;
  e.function_code = function_code;
  return e;
}

TEST(GatewayConfigWriter, AModbusRtuFileReadsBackIntoTheSameFields) {
  using hal::modbus::EntryKind;
  using hal::modbus::format_register_entry;
  const GatewayConfig g = settings();
  hal::modbus::ModbusDevice device;
  device.transport = "rtu";
  device.serial_port = "/dev/ttyUSB0";
  device.baud = 38400;
  device.parity = "E";
  device.unit_id = 7;
  device.response_timeout_ms = 250;
  hal::modbus::RegisterEntry echo = reg(300, 4);
  echo.type = "uint16";
  echo.eng_max = 65535.0;
  const std::string text =
      format_gateway_section(g) +
      format_device_section("modbus-rtu", g, hal::modbus::format_device_keys(device)) +
      format_setpoint(reflux(), format_register_entry(reg(100, 16), EntryKind::setpoint)) +
      values_text(format_register_entry(reg(200, 4), EntryKind::value),
                  format_register_entry(reg(100, 3), EntryKind::value),
                  format_register_entry(echo, EntryKind::value));
  const ConfigResult r = parse_gateway_config(text, "written.toml");
  ASSERT_TRUE(r.config) << r.error << "\n" << text;
  expect_read_back(*r.config);
  const hal::modbus::ModbusConfig* m = hal::modbus::modbus_config_of(*r.config->transport);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->device.transport, "rtu");
  EXPECT_EQ(m->device.serial_port, "/dev/ttyUSB0");
  EXPECT_EQ(m->device.baud, 38400);
  EXPECT_EQ(m->device.parity, "E");
  EXPECT_EQ(m->device.unit_id, 7);
  EXPECT_EQ(m->device.response_timeout_ms, 250);
}

TEST(GatewayConfigWriter, ATcpDeviceAndAClosedLoopSectionReadBack) {
  using hal::modbus::EntryKind;
  using hal::modbus::format_register_entry;
  GatewayConfig g = settings();
  g.simulator = false;
  g.peer_watchdog_s.reset();
  hal::modbus::ModbusDevice device;
  device.host = "plc-7.example";
  device.port = 5020;
  ClosedLoopSpec loop;
  loop.offsets = "mv";
  loop.controller = "dmc C-101 \"main\"";
  loop.controller_timeout_s = 90.0;
  loop.mv_baseline = {10.0};
  ValueSpec status;
  status.name = "st_reflux";
  status.role = ValueRole::mv_status;
  ValueSpec mode;
  mode.name = "mode";
  mode.role = ValueRole::controller_mode;
  ValueSpec command;
  command.name = "command";
  command.role = ValueRole::command;
  command.acknowledge = true;
  const auto code = [](std::uint32_t address, int function_code) {
    hal::modbus::RegisterEntry e = reg(address, function_code);
    e.type = "uint16";
    e.eng_max = 65535.0;
    return e;
  };
  const std::string text =
      format_gateway_section(g) + format_closed_loop_section(loop) +
      format_device_section("modbus-tcp", g, hal::modbus::format_device_keys(device)) +
      format_setpoint(reflux(), format_register_entry(reg(100, 16), EntryKind::setpoint)) +
      values_text(format_register_entry(reg(200, 4), EntryKind::value),
                  format_register_entry(reg(100, 3), EntryKind::value),
                  format_register_entry(code(410, 4), EntryKind::value)) +
      format_value(status, format_register_entry(code(411, 4), EntryKind::value)) +
      format_value(mode, format_register_entry(code(412, 4), EntryKind::value)) +
      format_value(command, format_register_entry(code(120, 3), EntryKind::value));
  const ConfigResult r = parse_gateway_config(text, "written.toml");
  ASSERT_TRUE(r.config) << r.error << "\n" << text;
  EXPECT_FALSE(r.config->simulator);
  EXPECT_FALSE(r.config->peer_watchdog_s);
  const hal::modbus::ModbusConfig* m = hal::modbus::modbus_config_of(*r.config->transport);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->device.host, "plc-7.example");
  EXPECT_EQ(m->device.port, 5020U);
  ASSERT_TRUE(r.config->closed_loop);
  EXPECT_EQ(r.config->closed_loop->offsets, "mv");
  EXPECT_EQ(r.config->closed_loop->controller, "dmc C-101 \"main\"");
  EXPECT_EQ(r.config->closed_loop->controller_timeout_s, 90.0);
  EXPECT_EQ(r.config->closed_loop->mv_baseline, std::vector<double>{10.0});
  ASSERT_EQ(r.config->values.size(), 6U);
  EXPECT_EQ(r.config->values[3].role, ValueRole::mv_status);
  EXPECT_EQ(r.config->values[4].role, ValueRole::controller_mode);
  EXPECT_EQ(r.config->values[5].role, ValueRole::command);
  EXPECT_TRUE(r.config->values[5].acknowledge);
}

TEST(GatewayConfigWriter, ACanFileReadsBackIntoTheSameFields) {
  const GatewayConfig g = settings();
  hal::can::CanConfig can;
  can.interface = "can0";
  can.value_timeout_ms = 500;
  const auto signal = [](std::uint32_t id, const char* type) {
    hal::can::CanSignal s;
    s.id = id;
    s.type = type;
    return s;
  };
  can.map.heartbeat = signal(0x201, "uint16");
  const auto frame = [&signal](std::uint32_t id) {
    return hal::can::format_can_entry(signal(id, "float32"));
  };
  const std::string text =
      format_gateway_section(g) + format_device_section("can", g, "") + "[can]\n" +
      hal::can::format_can_settings(can) + format_setpoint(reflux(), frame(0x200)) +
      values_text(frame(0x300), frame(0x301), hal::can::format_can_entry(signal(0x302, "uint16")));
  const ConfigResult r = parse_gateway_config(text, "written.toml");
  ASSERT_TRUE(r.config) << r.error << "\n" << text;
  expect_read_back(*r.config);
  EXPECT_EQ(r.config->transport->name(), "can");
}

// A role's name is one table for the reader and the writer.
TEST(GatewayConfigWriter, EveryRoleNameReadsBackAsItsRole) {
  for (const ValueRole role :
       {ValueRole::output, ValueRole::readback, ValueRole::heartbeat_echo, ValueRole::command,
        ValueRole::controller_mode, ValueRole::mv_status, ValueRole::controller_move,
        ValueRole::applied_mv, ValueRole::setpoint_in_force}) {
    EXPECT_EQ(role_of(role_name(role)), role) << role_name(role);
  }
  EXPECT_FALSE(role_of("heartbeat"));
}

}  // namespace
}  // namespace excite::app
