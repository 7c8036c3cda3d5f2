// SPDX-License-Identifier: MIT
// The gateway configuration file: the documented example parses; bad input is refused
// naming the file, the field, the value and what was expected.
#include "firmware/app/gateway_config.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace excite::app {
namespace {

const std::string kExample = EXCITE_EXAMPLE_CONFIG;

std::string example_text() {
  std::ifstream in(kExample);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
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
  EXPECT_EQ(c.modbus.device.port, 502U);
  EXPECT_EQ(c.modbus.map.setpoints[2].type, "int16");
  EXPECT_EQ(c.modbus.map.values[0].function_code, 4);
  EXPECT_EQ(output_indices(c), (std::vector<int>{0, 1, 2, 3}));
}

TEST(GatewayConfigTest, SecondsBecomeTicksOfThePeriod) {
  const ConfigResult r = load_gateway_config(kExample);
  ASSERT_TRUE(r.config);
  const engine::EngineConfig e = to_engine_config(*r.config, 60.0);
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

TEST(GatewayConfigTest, UnknownKeyIsRefusedWithTheKnownOnes) {
  std::string text = example_text();
  text.replace(text.find("ramp_s"), 6, "ramp_x");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("gw.toml: gateway.ramp_x = 300.0: expected one of the known keys"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, OverlappingSetpointsAreRefused) {
  std::string text = example_text();
  text.replace(text.find("address = 102"), 13, "address = 101");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[1].address = 101: expected no overlap with "
            "setpoints[0].address (registers 100..101)");
}

TEST(GatewayConfigTest, AddressBeyondTheProtocolIsRefused) {
  std::string text = example_text();
  text.replace(text.find("address = 106"), 13, "address = 65535");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("setpoints[3].address = 65535: expected address + 2 register(s) <= 65536"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, UnknownWordOrderIsRefused) {
  std::string text = example_text();
  text.replace(text.find("word_order = \"CDAB\""), 19, "word_order = \"BACD\"");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("setpoints[0].word_order = \"BACD\": expected ABCD, CDAB, BADC or DCBA"),
            std::string::npos)
      << e;
}

TEST(GatewayConfigTest, ReadbackMustNameAReadbackValue) {
  std::string text = example_text();
  text.replace(text.find("readback = \"L_sp\""), 17, "readback = \"xD\"");
  EXPECT_EQ(error_of(text),
            "gw.toml: setpoints[0].readback = \"xD\": expected the name of a value with role = "
            "\"readback\"");
}

TEST(GatewayConfigTest, InvalidChannelNameIsRefused) {
  std::string text = example_text();
  text.replace(text.find("name = \"xS\""), 11, "name = \"x S\"");
  const std::string e = error_of(text);
  EXPECT_NE(e.find("values[1].name = \"x S\": expected letters, digits"), std::string::npos) << e;
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
  EXPECT_EQ(error_of(text), "gw.toml: gateway.comm_loss = \"stop\": expected \"hold\" or \"ramp\"");
}

}  // namespace
}  // namespace excite::app
