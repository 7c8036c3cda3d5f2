// SPDX-License-Identifier: MIT
// The gateway configuration file: the documented example parses; bad input is refused
// naming the file, the field, the value and what was expected.
#include "firmware/app/gateway_config.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>

#include "firmware/app/closed_loop_log.hpp"
#include "hal/can/can_transport.hpp"
#include "hal/modbus/modbus_transport.hpp"

namespace excite::app {
namespace {

const std::string kExample = EXCITE_EXAMPLE_CONFIG;
const std::string kCanExample = EXCITE_CAN_EXAMPLE_CONFIG;

std::string example_text(const std::string& path = kExample) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// What the transport read: its own configuration (hal's transport seam).
const hal::modbus::ModbusConfig& modbus_of(const GatewayConfig& c) {
  const hal::modbus::ModbusConfig* m = hal::modbus::modbus_config_of(*c.transport);
  EXPECT_NE(m, nullptr);
  static const hal::modbus::ModbusConfig none;
  return m != nullptr ? *m : none;
}

const hal::can::CanConfig& can_of(const GatewayConfig& c) {
  const hal::can::CanConfig* can = hal::can::can_config_of(*c.transport);
  EXPECT_NE(can, nullptr);
  static const hal::can::CanConfig none;
  return can != nullptr ? *can : none;
}

std::string error_of(const std::string& text) {
  const ConfigResult r = parse_gateway_config(text, "gw.toml");
  EXPECT_FALSE(r.config.has_value());
  return r.error;
}

TEST(GatewayConfigTest, TheDocumentedExampleParses) {
  const ConfigResult r = load_gateway_config(kExample);
  ASSERT_TRUE(r.config) << r.error;
  const GatewayConfig& c = *r.config;
  EXPECT_EQ(c.setpoints.size(), 4U);
  EXPECT_EQ(c.values.size(), 10U);
  EXPECT_EQ(modbus_of(c).device.port, 502U);
  EXPECT_EQ(modbus_of(c).map.setpoints[2].type, "int16");
  EXPECT_EQ(modbus_of(c).map.values[0].function_code, 4);
  EXPECT_EQ(output_indices(c), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(c.transport->name(), "modbus-tcp");
  EXPECT_EQ(modbus_of(c).device.transport, "tcp");
  EXPECT_FALSE(c.simulator);
}

TEST(GatewayConfigTest, TransportNamesOldAndNew) {
  const std::pair<const char*, std::string_view> cases[] = {{"modbus-tcp", "modbus-tcp"},
                                                            {"tcp", "modbus-tcp"},
                                                            {"modbus-rtu", "modbus-rtu"},
                                                            {"rtu", "modbus-rtu"}};
  for (const auto& [name, transport] : cases) {
    std::string text = example_text();
    text.replace(text.find("\"modbus-tcp\""), 12, std::string("\"") + name + "\"");
    if (transport == "modbus-rtu") {
      text.replace(text.find("host = \"10.0.0.5\""), 17, "serial_port = \"/dev/ttyS0\"");
    }
    const ConfigResult r = parse_gateway_config(text, "gw.toml");
    ASSERT_TRUE(r.config) << name << ": " << r.error;
    EXPECT_EQ(r.config->transport->name(), transport) << name;
    EXPECT_EQ(modbus_of(*r.config).device.transport, transport == "modbus-tcp" ? "tcp" : "rtu");
  }
  std::string text = example_text();
  text.replace(text.find("\"modbus-tcp\""), 12, "\"udp\"");
  EXPECT_EQ(error_of(text),
            "gw.toml: device.transport = \"udp\", expected \"modbus-tcp\", \"modbus-rtu\" or "
            "\"can\" (\"tcp\" and \"rtu\" are still accepted)");
}

// Issue 39 §3: the command register acknowledged by clearing it — on the command value only,
// "clear" or "none".
TEST(GatewayConfigTest, TheCommandValueMayBeAcknowledgedByClearingIt) {
  const ConfigResult r = parse_gateway_config(example_text(), "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  const engine::EngineConfig e = to_engine_config(*r.config, std::chrono::minutes(1));
  EXPECT_TRUE(e.acknowledge_command);  // the example: acknowledge = "clear"
  std::string none = example_text();
  none.replace(none.find("acknowledge = \"clear\""), 21, "acknowledge = \"none\" ");
  const ConfigResult n = parse_gateway_config(none, "gw.toml");
  ASSERT_TRUE(n.config) << n.error;
  EXPECT_FALSE(to_engine_config(*n.config, std::chrono::minutes(1)).acknowledge_command);

  std::string bad = example_text();
  bad.replace(bad.find("acknowledge = \"clear\""), 21, "acknowledge = \"reset\"");
  EXPECT_NE(error_of(bad).find("values[9].acknowledge = \"reset\", expected \"clear\""),
            std::string::npos)
      << error_of(bad);
  std::string elsewhere = example_text();
  elsewhere.replace(elsewhere.find("role = \"heartbeat_echo\""), 23,
                    "role = \"heartbeat_echo\"\nacknowledge = \"clear\"");
  EXPECT_NE(error_of(elsewhere).find(".acknowledge = \"clear\", expected only on the command "
                                     "value (role = \"command\")"),
            std::string::npos)
      << error_of(elsewhere);
}

// Issue 26 §1: [segments] — the boundary period and the pre-approval, both optional.
TEST(GatewayConfigTest, SegmentsSectionSetsThePeriodAndThePreApproval) {
  const ConfigResult plain = parse_gateway_config(example_text(), "gw.toml");
  ASSERT_TRUE(plain.config) << plain.error;
  EXPECT_EQ(plain.config->segment_period_rows, 0U);
  EXPECT_EQ(plain.config->segment_preapproved_from, "");
  const std::string text =
      example_text() + "\n[segments]\nperiod_rows = 255\npreapproved_from = \"excite test\"\n";
  const ConfigResult r = parse_gateway_config(text, "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  EXPECT_EQ(r.config->segment_period_rows, 255U);
  EXPECT_EQ(r.config->segment_preapproved_from, "excite test");
  EXPECT_EQ(to_engine_config(*r.config, std::chrono::seconds(1)).segment_period_rows, 255U);
  EXPECT_NE(error_of(example_text() + "\n[segments]\nauto = true\n").find("segments.auto"),
            std::string::npos);
  EXPECT_NE(error_of(example_text() + "\n[segments]\npreapproved_from = \"\"\n")
                .find("segments.preapproved_from = \"\", expected one line of text, not empty"),
            std::string::npos);
  EXPECT_NE(error_of(example_text() + "\n[segments]\nperiod_rows = -1\n").find("period_rows"),
            std::string::npos);
}

// Issue 26 §4: [segments] await_s — wait at the table's end for the next segment.
TEST(GatewayConfigTest, SegmentsAwaitSecondsBecomeTicksAndAreRangeChecked) {
  const ConfigResult plain = parse_gateway_config(example_text(), "gw.toml");
  ASSERT_TRUE(plain.config) << plain.error;
  EXPECT_EQ(plain.config->segment_await_s, 0.0);
  EXPECT_EQ(to_engine_config(*plain.config, std::chrono::seconds(1)).segment_await_ticks, 0U);
  const ConfigResult r =
      parse_gateway_config(example_text() + "\n[segments]\nawait_s = 2.5\n", "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  EXPECT_EQ(r.config->segment_await_s, 2.5);
  EXPECT_EQ(to_engine_config(*r.config, std::chrono::seconds(1)).segment_await_ticks, 3U);
  EXPECT_NE(error_of(example_text() + "\n[segments]\nawait_s = -1\n")
                .find("segments.await_s = -1, expected 0 … 1e+06 seconds (0: the run ends at the "
                      "table's end)"),
            std::string::npos);
  // The example's commented [segments] block, uncommented, parses with its values.
  std::string example = example_text();
  const std::size_t from = example.find("# [segments]");
  ASSERT_NE(from, std::string::npos);
  std::string block;
  for (std::size_t at = from; at < example.size();) {
    const std::size_t eol = example.find('\n', at);
    std::string line = example.substr(at, eol - at);
    if (line.rfind("# ", 0) == 0 && line.find("#  ") != 0 && line.find('=') != std::string::npos)
      block += line.substr(2) + "\n";
    else if (line == "# [segments]")
      block += "[segments]\n";
    if (eol == std::string::npos) break;
    at = eol + 1;
  }
  const ConfigResult ex = parse_gateway_config(example_text() + "\n" + block, "gw.toml");
  ASSERT_TRUE(ex.config) << ex.error << "\n" << block;
  EXPECT_EQ(ex.config->segment_await_s, 600.0);
  EXPECT_EQ(ex.config->segment_period_rows, 255U);
  // The longest wait at the shortest period is the engine's longest duration, 1e9 ticks.
  GatewayConfig c = *r.config;
  c.segment_await_s = 1e6;
  c.heartbeat_max_lag_s = 0.01;
  EXPECT_EQ(check_timing(c, std::chrono::milliseconds(1)), "");
  const engine::EngineConfig e = to_engine_config(c, std::chrono::milliseconds(1));
  EXPECT_EQ(e.segment_await_ticks, engine::kMaxDurationTicks);
  EXPECT_TRUE(engine::validate(e)) << engine::validate(e).message();
}

TEST(GatewayConfigTest, SimulatorFlag) {
  std::string text = example_text();
  text.replace(text.find("# simulator = false"), 19, "simulator = true");
  const ConfigResult r = parse_gateway_config(text, "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  EXPECT_TRUE(r.config->simulator);
  text.replace(text.find("simulator = true"), 16, "simulator = 1");
  EXPECT_EQ(error_of(text), "gw.toml: device.simulator = 1, expected true or false");
}

TEST(GatewayConfigTest, TheCanExampleMapsSetpointsAndValuesToFrames) {
  const ConfigResult r = load_gateway_config(kCanExample);
  ASSERT_TRUE(r.config) << r.error;
  const GatewayConfig& c = *r.config;
  EXPECT_EQ(c.transport->name(), "can");
  EXPECT_EQ(can_of(c).interface, "can0");
  EXPECT_EQ(can_of(c).value_timeout_ms, 500);
  ASSERT_EQ(can_of(c).map.setpoints.size(), 2U);
  EXPECT_EQ(can_of(c).map.setpoints[1].id, 0x210U);
  EXPECT_EQ(can_of(c).map.setpoints[1].byte_offset, 2U);
  EXPECT_EQ(can_of(c).map.setpoints[1].type, "int16");
  EXPECT_EQ(can_of(c).map.setpoints[1].scale, 0.001);
  ASSERT_TRUE(can_of(c).map.heartbeat.has_value());
  EXPECT_EQ(can_of(c).map.heartbeat->id, 0x210U);
  EXPECT_EQ(can_of(c).map.heartbeat->byte_offset, 4U);
  ASSERT_EQ(can_of(c).map.values.size(), 6U);
  EXPECT_EQ(can_of(c).map.values[1].type, "float32");
  EXPECT_EQ(can_of(c).map.values[1].byte_offset, 4U);
  EXPECT_EQ(can_of(c).map.values[5].id, 0x311U);
  EXPECT_EQ(hal::modbus::modbus_config_of(*c.transport), nullptr);
  const engine::EngineConfig e = to_engine_config(c, std::chrono::minutes(1));
  EXPECT_EQ(e.input[1].readback, 3);
  EXPECT_EQ(e.heartbeat_echo, 4);
  EXPECT_EQ(e.command_value, 5);
}

// One writer beside the reader (issue 24 §4): what format_can_settings and format_can_entry
// write of every field, the CAN transport reads back the same.
TEST(GatewayConfigTest, TheCanWriterWritesWhatTheReaderReadsBack) {
  hal::can::CanConfig written;
  written.interface = "vcan3";
  written.value_timeout_ms = 750;
  written.enobufs_limit = 4;
  written.bitrate = 250000;
  hal::can::CanSignal sp;
  sp.name = "L";
  sp.id = 0x1ABCDE;
  sp.extended = true;
  sp.byte_offset = 2;
  sp.type = "int16";
  sp.byte_order = "big";
  sp.scale = 0.001;
  sp.offset = 1.5;
  hal::can::CanSignal pv{"xD", 0x310, false, 4, "float32", "little", 1.0, 0.0};
  hal::can::CanSignal rb{"L_sp", 0x311, false, 0, "int16", "big", 0.001, 1.5};
  hal::can::CanSignal hb{"heartbeat", 0x1ABCDE, true, 0, "uint8", "big", 1.0, 0.0};
  written.map.setpoints = {sp};
  written.map.values = {pv, rb};
  written.map.heartbeat = hb;
  const std::string text = "[gateway]\nplant = \"p\"\n[device]\ntransport = \"can\"\n[can]\n" +
                           hal::can::format_can_settings(written) +
                           "[[setpoints]]\nname = \"L\"\nmin = 1.0\nmax = 2.0\nmax_move = 0.5\n"
                           "readback = \"L_sp\"\n" +
                           hal::can::format_can_entry(sp) + "[[values]]\nname = \"xD\"\n" +
                           hal::can::format_can_entry(pv) +
                           "[[values]]\nname = \"L_sp\"\nrole = \"readback\"\n" +
                           hal::can::format_can_entry(rb);
  const ConfigResult r = parse_gateway_config(text, "gw.toml");
  ASSERT_TRUE(r.config) << r.error << "\n" << text;
  const hal::can::CanConfig& read = can_of(*r.config);
  EXPECT_EQ(read.interface, written.interface);
  EXPECT_EQ(read.value_timeout_ms, written.value_timeout_ms);
  EXPECT_EQ(read.enobufs_limit, written.enobufs_limit);
  EXPECT_EQ(read.bitrate, written.bitrate);
  const auto same = [](const hal::can::CanSignal& a, const hal::can::CanSignal& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.extended, b.extended);
    EXPECT_EQ(a.byte_offset, b.byte_offset);
    EXPECT_EQ(a.type, b.type);
    EXPECT_EQ(a.byte_order, b.byte_order);
    EXPECT_EQ(a.scale, b.scale);
    EXPECT_EQ(a.offset, b.offset);
  };
  ASSERT_EQ(read.map.setpoints.size(), 1U);
  same(read.map.setpoints[0], sp);
  ASSERT_EQ(read.map.values.size(), 2U);
  same(read.map.values[0], pv);
  same(read.map.values[1], rb);
  ASSERT_TRUE(read.map.heartbeat.has_value());
  same(*read.map.heartbeat, hb);
}

TEST(GatewayConfigTest, CanFrameLayoutErrorsNameTheKeyOfTheFile) {
  std::string text = example_text(kCanExample);
  text.replace(text.find("byte_offset = 2"), 15, "byte_offset = 1");  // V over L's byte 1
  std::string e = error_of(text);
  EXPECT_NE(e.find("gw.toml: setpoints[1].byte_offset = 1, expected no overlap with "
                   "setpoints[0] in frame 0x210"),
            std::string::npos)
      << e;
  text = example_text(kCanExample);
  text.replace(text.find("can_id = 0x310"), 14, "can_id = 0x800");
  EXPECT_EQ(error_of(text),
            "gw.toml: values[0].can_id = 0x800, expected 0x0..0x7FF (11-bit identifier; set "
            "extended for 29-bit)");
  text = example_text(kCanExample);
  text.replace(text.find("heartbeat_type = \"uint16\""), 25, "heartbeat_type = \"int32\"");
  EXPECT_EQ(error_of(text),
            "gw.toml: can.heartbeat_type = \"int32\", expected uint8 or uint16 (a counter)");
}

TEST(GatewayConfigTest, TransportSpecificKeysAndSectionsAreChecked) {
  std::string text = example_text(kCanExample);  // a Modbus key under CAN
  text.replace(text.find("byte_offset = 0"), 15, "address = 100");
  std::string e = error_of(text);
  EXPECT_NE(e.find("gw.toml:32:11: setpoints[0].address = 100 (unknown key), expected one of the "
                   "known keys: byte_offset, byte_order, can_id"),
            std::string::npos)
      << e;
  text = example_text(kCanExample);
  text.replace(text.find("[can]"), 5, "[canbus]");
  e = error_of(text);
  EXPECT_NE(e.find("canbus"), std::string::npos) << e;
  text = example_text(kCanExample);
  text.replace(text.find("interface = \"can0\""), 18, "");
  EXPECT_EQ(error_of(text),
            "gw.toml: can.interface = (missing), expected a SocketCAN interface, e.g. can0");
  text = example_text();
  text += "\n[can]\ninterface = \"can0\"\n";
  EXPECT_EQ(error_of(text),
            "gw.toml: can = a table, expected no [can] section with transport = \"modbus-tcp\"");
  text = example_text(kCanExample);
  text.replace(text.find("can_id = 0x311\nbyte_offset = 6"), 14, "can_id = 0x210");
  e = error_of(text);
  EXPECT_NE(e.find("values[5].can_id = 0x210, expected an identifier not also used for "
                   "setpoints"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, SetpointLimitsBeyondTheRegisterAreRefused) {
  std::string text = example_text();  // S: int16, eng 0..2 on raw 0..27648
  text.replace(text.find("max = 1.8"), 9, "max = 2.5");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[2].max = 2.5, expected <= 2, the most register 104 int16 raw "
            "0..27648 = 0..2 can carry");
  text = example_text();
  text.replace(text.find("min = 0.2"), 9, "min = -0.5");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[2].min = -0.5, expected >= 0, the least register 104 int16 raw "
            "0..27648 = 0..2 can carry");
  text = example_text(kCanExample);  // L: int16 at 0.001 kmol/min per count
  text.replace(text.find("max = 3.5"), 9, "max = 40.0");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[0].max = 40, expected <= 32.767, the most CAN 0x210 "
            "int16 scale 0.001 offset 0 can carry");
}

TEST(GatewayConfigTest, SecondsBecomeTicksOfThePeriod) {
  const ConfigResult r = load_gateway_config(kExample);
  ASSERT_TRUE(r.config);
  const engine::EngineConfig e = to_engine_config(*r.config, std::chrono::seconds(60));
  EXPECT_EQ(e.ramp_ticks, 5U);               // 300 s
  EXPECT_EQ(e.resume_dwell_ticks, 10U);      // 600 s
  EXPECT_EQ(e.suspend_timeout_ticks, 120U);  // 7200 s
  EXPECT_EQ(e.heartbeat_max_lag, 3U);        // 180 s
  EXPECT_EQ(e.input[0].readback, 4);         // L_sp
  EXPECT_EQ(e.heartbeat_echo, 8);
  EXPECT_EQ(e.command_value, 9);
  EXPECT_TRUE(e.test[0].enabled);
  EXPECT_FALSE(e.test[1].enabled);
  EXPECT_TRUE(engine::validate(e));
}

// Found with tests/fuzz/gateway_config_fuzz (UBSan: 1.66667e+10 is outside the range of
// representable values of type 'unsigned int'): a duration of more ticks than a uint32 holds
// was cast out of range. The file's value is refused by check_timing (GatewayTiming.*); the
// conversion itself saturates for a configuration built in code.
TEST(GatewayConfigTest, DurationsBeyondTheTickCounterSaturate) {
  const ConfigResult r = parse_gateway_config(example_text(), "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  GatewayConfig c = *r.config;
  c.ramp_s = 1e12;
  EXPECT_NE(check_timing(c, std::chrono::seconds(60)), "");
  const engine::EngineConfig e = to_engine_config(c, std::chrono::seconds(60));
  EXPECT_EQ(e.ramp_ticks, 4294967295U);  // 1.7e10 ticks of 60 s
  EXPECT_EQ(e.resume_dwell_ticks, 10U);  // the others as before
  EXPECT_FALSE(engine::validate(e));     // and the engine refuses that many ticks
}

TEST(GatewayConfigTest, VerifiedWritesTakeTheResolutionOfBothEncodings) {
  std::string text = example_text();
  text.replace(text.find("readback_lag_ticks = 1"), 22, "readback_lag_ticks = 2");
  const ConfigResult r = parse_gateway_config(text, "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  const engine::EngineConfig e = to_engine_config(*r.config, std::chrono::seconds(60));
  EXPECT_TRUE(e.verify_readbacks);
  EXPECT_EQ(e.readback_lag_ticks, 2U);
  EXPECT_EQ(e.readback_mismatch_limit, 3U);
  EXPECT_EQ(e.input[0].readback_rel_tol, 0x1p-23);  // L: float32 written and read
  EXPECT_EQ(e.input[0].readback_abs_tol, 0.0);
  EXPECT_EQ(e.input[2].readback_abs_tol, 2.0 / 27648);  // S: int16 raw 0..27648 = 0..2
  EXPECT_EQ(e.input[2].readback_rel_tol, 0.0);
  text.replace(text.find("readback_lag_ticks = 2"), 22, "readback_lag_ticks = 17");
  EXPECT_NE(error_of(text).find("gateway.readback_lag_ticks = 17"), std::string::npos)
      << error_of(text);
}

TEST(GatewayConfigTest, AReadbackOfTheSetpointRegisterMustUseItsEncoding) {
  std::string text = example_text();
  const auto at = text.find("name = \"V_sp\"");
  text.replace(text.find("word_order = \"CDAB\"", at), 19, "word_order = \"ABCD\"");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[1] (V) register 102 = float32 CDAB, expected the encoding its "
            "readback V_sp reads the same register with (float32 ABCD)");
}

TEST(GatewayConfigTest, RegisterFieldsAreReadByTheSharedSchemaWithTheirPosition) {
  // hal/modbus/register_entry_toml.hpp: the plant server reads the same keys, the same way.
  std::string text = example_text();
  const std::size_t at = text.find("address = ", text.find("[[values]]"));
  text.replace(at, text.find('\n', at) - at, "address = 70000");
  const std::string e = error_of(text);
  EXPECT_EQ(e.rfind("gw.toml:", 0), 0u) << e;
  EXPECT_NE(e.find(": values[0].address = 70000, expected a register address 0..65535"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, UnknownKeyIsRefusedWithTheKnownOnes) {
  std::string text = example_text();
  text.replace(text.find("ramp_s"), 6, "ramp_x");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("gw.toml:7:10: gateway.ramp_x = 300.0 (unknown key), expected one of the known "
                   "keys: comm_fail_limit"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, OverlappingSetpointsAreRefused) {
  std::string text = example_text();
  text.replace(text.find("address = 102"), 13, "address = 101");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[1].address = 101, expected no overlap with "
            "setpoints[0].address (registers 100..101)");
}

TEST(GatewayConfigTest, AddressBeyondTheProtocolIsRefused) {
  std::string text = example_text();
  text.replace(text.find("address = 106"), 13, "address = 65535");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("setpoints[3].address = 65535, expected address + 2 register(s) <= 65536"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, UnknownWordOrderIsRefused) {
  std::string text = example_text();
  text.replace(text.find("word_order = \"CDAB\""), 19, "word_order = \"BACD\"");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("setpoints[0].word_order = \"BACD\", expected ABCD, CDAB, BADC or DCBA"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, ReadbackMustNameAReadbackValue) {
  std::string text = example_text();
  text.replace(text.find("readback = \"L_sp\""), 17, "readback = \"xD\"");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[0].readback = \"xD\", expected the name of a value with role = "
            "\"readback\"");
}

TEST(GatewayConfigTest, InvalidChannelNameIsRefused) {
  std::string text = example_text();
  text.replace(text.find("name = \"xS\""), 11, "name = \"x S\"");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("values[1].name = \"x S\", expected letters, digits"), std::string::npos) << e;
}

TEST(GatewayConfigTest, HysteresisLeavingNoBandIsRefused) {
  std::string text = example_text();
  text.replace(text.find("hysteresis = 0.01"), 17, "hysteresis = 0.06");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("values[0].hysteresis = 0.06"), std::string::npos) << e;
}

TEST(GatewayConfigTest, TomlSyntaxErrorNamesLineAndColumn) {
  const std::string e = error_of("[gateway\nplant = 1\n");
  EXPECT_EQ(e.rfind("gw.toml:1:", 0), 0U) << e;  // file:line:column: what
}

TEST(GatewayConfigTest, UnknownCommLossActionIsRefused) {
  std::string text = example_text();
  text.replace(text.find("comm_loss = \"hold\""), 18, "comm_loss = \"stop\"");
  EXPECT_EQ(error_of(text), "gw.toml: gateway.comm_loss = \"stop\", expected \"hold\" or \"ramp\"");
}

// ---- Issue 11 item 2: absurd timing is refused before the gateway runs ----

// The example with `key = value` put into [gateway] (replacing the key's line if present).
std::string with_gateway_key(const std::string& key, const std::string& value) {
  std::string text = example_text();
  const std::size_t at = text.find("\n" + key + " = ");
  if (at != std::string::npos) {
    const std::size_t end = text.find('\n', at + 1);
    text.erase(at + 1, end - at);  // the line and its newline
  }
  text.insert(text.find("[gateway]\n") + 10, key + " = " + value + "\n");
  return text;
}

TEST(GatewayTiming, PeriodOutsideItsRangeIsRefused) {
  EXPECT_EQ(error_of(with_gateway_key("period_s", "1e-9")),
            "gw.toml: gateway.period_s = 1e-09, expected 0.001 … 86400 seconds");
  EXPECT_EQ(error_of(with_gateway_key("period_s", "0")),
            "gw.toml: gateway.period_s = 0, expected 0.001 … 86400 seconds");
  EXPECT_EQ(error_of(with_gateway_key("period_s", "1e300")),
            "gw.toml: gateway.period_s = 1e+300, expected 0.001 … 86400 seconds");
  EXPECT_EQ(error_of(with_gateway_key("period_s", "nan")),
            "gw.toml:5:12: gateway.period_s = nan, expected a finite number");
  EXPECT_TRUE(parse_gateway_config(with_gateway_key("period_s", "0.001"), "gw.toml").config);
}

TEST(GatewayTiming, RampOutsideItsRangeIsRefused) {
  EXPECT_EQ(error_of(with_gateway_key("ramp_s", "1e300")),
            "gw.toml: gateway.ramp_s = 1e+300, expected 0 … 1e+06 seconds");
  EXPECT_EQ(error_of(with_gateway_key("ramp_s", "-1")),
            "gw.toml: gateway.ramp_s = -1, expected 0 … 1e+06 seconds");
  EXPECT_EQ(error_of(with_gateway_key("ramp_s", "inf")),
            "gw.toml:5:10: gateway.ramp_s = inf, expected a finite number");
}

TEST(GatewayTiming, ResumeDwellOutsideItsRangeIsRefused) {
  EXPECT_EQ(error_of(with_gateway_key("resume_dwell_s", "2e6")),
            "gw.toml: gateway.resume_dwell_s = 2e+06, expected 0 … 1e+06 seconds");
}

TEST(GatewayTiming, SuspendTimeoutOutsideItsRangeIsRefused) {
  EXPECT_EQ(error_of(with_gateway_key("suspend_timeout_s", "-0.5")),
            "gw.toml: gateway.suspend_timeout_s = -0.5, expected 0 … 1e+06 seconds");
}

TEST(GatewayTiming, HeartbeatLagOutsideItsRangeIsRefused) {
  EXPECT_EQ(error_of(with_gateway_key("heartbeat_max_lag_s", "1e7")),
            "gw.toml: gateway.heartbeat_max_lag_s = 1e+07, expected 0 … 1e+06 seconds");
  // Within the seconds range but beyond the engine's 30000 ticks at this period: refused
  // when the period is known (before, it was silently clamped).
  const ConfigResult r =
      parse_gateway_config(with_gateway_key("heartbeat_max_lag_s", "40000"), "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  EXPECT_EQ(check_timing(*r.config, std::chrono::seconds(1)),
            "gw.toml: gateway.heartbeat_max_lag_s = 40000 (40000 ticks of 1 s), expected 0 … "
            "30000 seconds (30000 ticks) at this period");
  EXPECT_EQ(check_timing(*r.config, std::chrono::seconds(2)), "");
}

TEST(GatewayTiming, DurationsBeyondTheEngineTicksAtThePlansPeriodAreRefused) {
  // No period_s: the plan's sample time is the period; 1e6 s at 1 ms = 1e9 ticks (the most).
  const ConfigResult r = parse_gateway_config(with_gateway_key("ramp_s", "1e6"), "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  EXPECT_EQ(check_timing(*r.config, std::chrono::milliseconds(1)),
            "gw.toml: gateway.heartbeat_max_lag_s = 180 (180000 ticks of 0.001 s), expected 0 … "
            "30 seconds (30000 ticks) at this period");
  GatewayConfig c = *r.config;
  c.heartbeat_max_lag_s = 0;  // the default, 3 ticks
  EXPECT_EQ(check_timing(c, std::chrono::milliseconds(1)), "");
  EXPECT_EQ(to_engine_config(c, std::chrono::milliseconds(1)).ramp_ticks, 1'000'000'000U);
  EXPECT_TRUE(engine::validate(to_engine_config(c, std::chrono::milliseconds(1))));
  EXPECT_EQ(check_timing(c, std::chrono::duration<double>(1e-9 * 60)),
            "gw.toml: the plan's sample time (as the tick period; gateway.period_s unset) = "
            "6.000000000000001e-08 s, expected 0.001 … 86400 seconds");
  EXPECT_EQ(check_timing(c, std::chrono::duration<double>(1e9)),
            "gw.toml: the plan's sample time (as the tick period; gateway.period_s unset) = "
            "1e+09 s, expected 0.001 … 86400 seconds");
}

TEST(GatewayTiming, ToEngineConfigSaturatesInsteadOfOverflowing) {
  GatewayConfig c = *load_gateway_config(kExample).config;
  c.ramp_s = 1e300;  // past check_timing: the conversion itself must stay defined (UBSan)
  c.suspend_timeout_s = std::numeric_limits<double>::quiet_NaN();
  const engine::EngineConfig e = to_engine_config(c, std::chrono::seconds(1));
  EXPECT_EQ(e.ramp_ticks, std::numeric_limits<std::uint32_t>::max());
  EXPECT_EQ(e.suspend_timeout_ticks, 0U);
  EXPECT_FALSE(engine::validate(e));  // and the engine refuses it by name
  EXPECT_NE(std::string(engine::validate(e).message()).find("ramp_ticks = 4294967295"),
            std::string::npos);
}

TEST(GatewayTiming, CountsOutsideTheirRangeAreRefused) {
  EXPECT_EQ(error_of(with_gateway_key("comm_fail_limit", "0")),
            "gw.toml:5:19: gateway.comm_fail_limit = 0, expected an integer 1..1000000");
  EXPECT_EQ(error_of(with_gateway_key("log_ring", "8")),
            "gw.toml:5:12: gateway.log_ring = 8, expected an integer 16..1048576");
  EXPECT_EQ(error_of(with_gateway_key("readback_mismatch_limit", "-1")),
            "gw.toml:5:27: gateway.readback_mismatch_limit = -1, expected an integer 0..1000000");
  std::string text = example_text();
  text.replace(text.find("response_timeout_ms = 200"), 25, "response_timeout_ms = 0");
  EXPECT_EQ(error_of(text),
            "gw.toml:25:23: device.response_timeout_ms = 0, expected an integer 1..60000");
}

// Closed loop (issue 42 §2): [closed_loop] and the controller's read-back roles.
std::string closed_loop_text(const std::string& closed, int statuses) {
  std::string text = example_text() + "\n" + closed + "\n";
  text +=
      "[[values]]\nname = \"mode\"\nrole = \"controller_mode\"\naddress = 500\n"
      "function_code = 4\ntype = \"uint16\"\neng_min = 0\neng_max = 65535\n";
  for (int i = 0; i < statuses; ++i) {
    text += "[[values]]\nname = \"st" + std::to_string(i) +
            "\"\nrole = \"mv_status\"\naddress = " + std::to_string(510 + i) +
            "\nfunction_code = 4\ntype = \"uint16\"\neng_min = 0\neng_max = 65535\n";
  }
  return text;
}

TEST(GatewayConfigTest, ClosedLoopRolesMapToTheEnginesControllerWatch) {
  const ConfigResult r = parse_gateway_config(
      closed_loop_text("[closed_loop]\noffsets = \"mv\"\ncontroller_timeout_s = 2.5", 2),
      "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  ASSERT_TRUE(r.config->closed_loop);
  EXPECT_EQ(r.config->closed_loop->offsets, "mv");
  const engine::EngineConfig e = to_engine_config(*r.config, std::chrono::duration<double>(0.5));
  EXPECT_EQ(e.controller.mode, 10);
  EXPECT_EQ(e.controller.mvs, 2U);
  EXPECT_EQ(e.controller.status[1], 12);
  EXPECT_EQ(e.controller.move[0], engine::kNone);
  EXPECT_EQ(e.controller.timeout_ticks, 5U);
  EXPECT_TRUE(engine::validate(e)) << engine::validate(e).message();
}

TEST(GatewayConfigTest, ClosedLoopRefusalsNameTheField) {
  EXPECT_NE(error_of(closed_loop_text("", 1))
                .find("values[10].role = \"(closed-loop role)\", expected a [closed_loop] table"),
            std::string::npos)
      << error_of(closed_loop_text("", 1));
  EXPECT_NE(error_of(closed_loop_text("[closed_loop]\noffsets = \"cv\"", 1))
                .find("closed_loop.offsets = \"cv\", expected \"mv\" (MV test offsets)"),
            std::string::npos);
  EXPECT_NE(error_of(closed_loop_text("[closed_loop]\ncontroller = \"pi\"", 1))
                .find("closed_loop.offsets = (missing)"),
            std::string::npos);
  EXPECT_NE(error_of(closed_loop_text("[closed_loop]\noffsets = \"mv\"", 0))
                .find("values = 0 mv_status values, expected 1 … 8 under [closed_loop]"),
            std::string::npos)
      << error_of(closed_loop_text("[closed_loop]\noffsets = \"mv\"", 0));
  EXPECT_NE(
      error_of(closed_loop_text("[closed_loop]\noffsets = \"mv\"\ncontroller_timeout_s = -1", 1))
          .find("closed_loop.controller_timeout_s = -1, expected 0 … "),
      std::string::npos);
}

// Run-log v4 (README "Closed loop", the run log): the log's inputs are the MVs, r the offsets.
// The example's 4 setpoints under "both" with 2 MVs: setpoints 0, 1 are the MV offsets,
// 2, 3 the setpoint offsets of the outputs 0, 1; the outputs' r columns come first.
TEST(GatewayConfigTest, ClosedLoopLogLayoutMapsTheOffsetsToRChannels) {
  const ConfigResult r = parse_gateway_config(
      closed_loop_text("[closed_loop]\noffsets = \"both\"\nmv_baseline = [2.5, 3.5]", 2),
      "gw.toml");
  ASSERT_TRUE(r.config) << r.error;
  std::vector<runlog::Channel> inputs;
  const ClosedLoopLogLayout both = closed_loop_log_layout(*r.config, 4, inputs);
  EXPECT_EQ(both.excitation, runlog::Excitation::both);
  EXPECT_EQ(both.r_channels, (std::vector<std::size_t>{0, 1, 4, 5}));
  EXPECT_EQ(both.r_source, (std::vector<std::uint32_t>{2, 3, 0, 1}));
  EXPECT_EQ(both.mv_baseline, (std::vector<double>{2.5, 3.5}));
  ASSERT_EQ(inputs.size(), 2U);
  EXPECT_EQ(inputs[0].name, "st0") << "no applied_mv value: the mv_status value's name";

  const ConfigResult mv =
      parse_gateway_config(closed_loop_text("[closed_loop]\noffsets = \"mv\"", 2), "gw.toml");
  ASSERT_TRUE(mv.config) << mv.error;
  const ClosedLoopLogLayout m = closed_loop_log_layout(*mv.config, 4, inputs);
  EXPECT_EQ(m.r_channels, (std::vector<std::size_t>{0, 1})) << "one per MV, not per setpoint";
  EXPECT_EQ(m.mv_baseline, (std::vector<double>{0.0, 0.0}));

  EXPECT_NE(
      error_of(closed_loop_text("[closed_loop]\noffsets = \"mv\"\nmv_baseline = [1.0]", 2))
          .find("closed_loop.mv_baseline = 1 numbers, expected none or one per mv_status value "
                "(2)"),
      std::string::npos)
      << error_of(closed_loop_text("[closed_loop]\noffsets = \"mv\"\nmv_baseline = [1.0]", 2));
}

}  // namespace
}  // namespace excite::app
