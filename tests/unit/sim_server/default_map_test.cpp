// SPDX-License-Identifier: MIT
// The default register map (derived from the plant) and the configuration writer: the map
// compiles against its plant in lock-step mode, has the documented addresses, and a written
// configuration parses back to the same configuration.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "sim/server/config_writer.hpp"
#include "sim/server/default_map.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

using ::testing::HasSubstr;

TEST(DefaultMap, HasTheDocumentedAddressesAndCompilesInLockstep) {
  ServerConfig config;
  config.registers = default_registers(4, 3, {"L", "V", "S", "F"}, {});
  const ServerLayout layout = compile_layout(config, 4, 3, /*lockstep=*/true, "default");
  ASSERT_EQ(layout.setpoints.size(), 4U);
  for (std::uint32_t i = 0; i < 4; ++i) EXPECT_EQ(layout.setpoints[i].address, 100 + 2 * i);
  for (std::uint32_t j = 0; j < 3; ++j) {
    EXPECT_EQ(layout.values[j].address, 200 + 2 * j);
    EXPECT_TRUE(layout.values[j].input_table);
  }
  EXPECT_EQ(layout.heartbeat_address, 108U);
  EXPECT_EQ(layout.heartbeat_echo.address, 300U);
  EXPECT_TRUE(layout.heartbeat_echo.input_table);
  EXPECT_EQ(layout.command_address, 301U);
  EXPECT_EQ(layout.control_address, 400U);
  EXPECT_EQ(config.registers.map.setpoints[2].name, "S");
  EXPECT_EQ(config.registers.map.values[1].name, "y2");  // no names given: y1, y2, ...
}

TEST(DefaultMap, LargestPlantsFitAndBeyondIsRefusedByName) {
  ServerConfig config;
  config.registers = default_registers(default_max_inputs, default_max_outputs);
  EXPECT_NO_THROW(compile_layout(config, default_max_inputs, default_max_outputs, true));
  try {
    default_registers(default_max_inputs + 1, 2);
    FAIL() << "100 inputs accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("plant = 100 inputs, 2 outputs, expected 1..99 inputs"));
  }
}

TEST(ConfigWriter, WrittenConfigurationParsesBackIdentically) {
  ServerConfig config;
  config.plant.library = "alatiqi4x4";
  config.plant.sample_time_min = 0.5;
  config.plant.input_baseline = {2.706290012345678, 0.1, -3.0, 1e-9};
  config.plant.output_baseline = {0.99, 0.01, 0.5, 1.0 / 3.0};
  config.plant.noise_variance = {1e-8};
  config.plant.noise_seed = 42;
  config.registers = default_registers(4, 4);
  config.registers.map.values[3].type = "int16";  // a scaled value round-trips too
  config.registers.map.values[3].eng_min = -20.0;
  config.registers.map.values[3].eng_max = 20.0;
  config.registers.map.values[3].raw_min = -27648;
  config.registers.map.values[3].raw_max = 27648;
  const std::string text = format_server_config(config, "a header");
  const ServerConfig back = parse_server_config(text, "written");
  EXPECT_EQ(back.plant.library, "alatiqi4x4");
  EXPECT_EQ(back.plant.sample_time_min, 0.5);
  EXPECT_EQ(back.plant.input_baseline, config.plant.input_baseline);  // bit for bit
  EXPECT_EQ(back.plant.output_baseline, config.plant.output_baseline);
  EXPECT_EQ(back.plant.noise_variance, config.plant.noise_variance);
  EXPECT_EQ(back.plant.noise_seed, 42U);
  EXPECT_EQ(back.registers.command_address, 301U);
  EXPECT_EQ(back.registers.control_address, 400U);
  EXPECT_EQ(back.registers.map.heartbeat_address, 108U);
  ASSERT_EQ(back.registers.map.values.size(), 4U);
  EXPECT_EQ(back.registers.map.values[3].type, "int16");
  EXPECT_EQ(back.registers.map.values[3].raw_min, -27648);
  EXPECT_EQ(back.registers.map.values[0].name, "y1");
  EXPECT_EQ(back.registers.map.setpoints[1].address, 102U);
}

TEST(ConfigWriter, NumbersAreExactAndAlwaysFloats) {
  EXPECT_EQ(toml_number(1.0), "1.0");
  EXPECT_EQ(toml_number(-3.0), "-3.0");
  EXPECT_EQ(toml_number(0.1), "0.1");
  EXPECT_EQ(toml_number(0.03), "0.03");
  EXPECT_EQ(toml_number(2.706290012345678), "2.706290012345678");
  EXPECT_EQ(toml_number(1e-8), "1e-08");
  EXPECT_EQ(toml_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
}

}  // namespace
}  // namespace excite::sim::server
