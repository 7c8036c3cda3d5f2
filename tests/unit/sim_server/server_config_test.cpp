// SPDX-License-Identifier: MIT
// The excite-plant configuration: parsing, the register map checks (hal's and the plant
// side's), and the layout checked against the plant.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "sim/library/library.hpp"
#include "sim/server/config_writer.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

using ::testing::HasSubstr;

// A 2×2 map: two float32 setpoints, heartbeat after them, echo and values in input registers.
std::string two_by_two(const std::string& extra_registers = "",
                       const std::string& first_word_order = "CDAB") {
  return R"(
[plant]
library = "woodberry2x2"
sample_time_min = 1.0
input_baseline = [1.95, 1.71]
output_baseline = [96.0, 0.5]

[registers]
heartbeat_address = 104
heartbeat_echo_address = 10
heartbeat_echo_function_code = 4
)" + extra_registers +
         R"(
[[registers.setpoints]]
name = "R"
address = 100
word_order = ")" +
         first_word_order + R"("

[[registers.setpoints]]
name = "S"
address = 102

[[registers.values]]
name = "xD"
address = 0
function_code = 4

[[registers.values]]
name = "xB"
address = 2
function_code = 4
type = "uint16"
eng_min = 0
eng_max = 1
)";
}

// The message of the std::invalid_argument `f` throws ("" if none).
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ServerConfig, TheDocumentedExampleParsesAndFitsItsPlant) {
  const ServerConfig config = load_server_config(EXCITE_PLANT_EXAMPLE);
  EXPECT_EQ(config.plant.library, "alatiqi4x4");
  ASSERT_EQ(config.registers.map.setpoints.size(), 4U);
  ASSERT_EQ(config.registers.map.values.size(), 4U);
  EXPECT_EQ(config.registers.map.setpoints[0].word_order, "CDAB");
  EXPECT_EQ(config.registers.map.setpoints[3].type, "int16");
  EXPECT_EQ(config.registers.map.setpoints[3].raw_max, 27648);
  EXPECT_EQ(config.registers.map.heartbeat_address, 108U);
  EXPECT_EQ(config.registers.heartbeat_echo_function_code, 4);
  EXPECT_EQ(config.registers.control_address, 400U);
  const auto plant = load_plant(config.plant, config.base_directory);
  const ServerLayout layout = compile_layout(config, plant->inputs(), plant->outputs(), true);
  EXPECT_EQ(layout.holding.start, 100U);
  EXPECT_EQ(layout.holding.count, 308U);  // 100..407: setpoints, heartbeat, y3, control
  EXPECT_EQ(layout.input.start, 200U);
  EXPECT_EQ(layout.input.count, 101U);  // 200..300: values and echo
  EXPECT_TRUE(layout.values[2].input_table == false);
  EXPECT_TRUE(layout.heartbeat_echo.input_table);
}

TEST(ServerConfig, DefaultsAreFloat32AbcdAndFc16ForSetpoints) {
  const ServerConfig config = parse_server_config(two_by_two());
  const auto& sp = config.registers.map.setpoints[1];
  EXPECT_EQ(sp.type, "float32");
  EXPECT_EQ(sp.word_order, "ABCD");
  EXPECT_EQ(sp.function_code, 16);
  EXPECT_EQ(config.plant.noise_seed, 1U);
  EXPECT_TRUE(config.plant.noise_variance.empty());
}

TEST(ServerConfig, UnknownTopLevelKeyIsNamed) {
  const std::string e =
      error_of([] { parse_server_config("[plantt]\n" + two_by_two(), "c.toml"); });
  EXPECT_THAT(e, HasSubstr("c.toml:1:1: plantt = (a table) (unknown key), expected one of the "
                           "known keys: plant, registers"));
}

TEST(ServerConfig, UnknownEntryKeyIsNamedWithItsIndex) {
  std::string text = two_by_two();
  text.replace(text.find("name = \"S\""), 10, "nmae = \"S\"");
  const std::string e = error_of([&] { parse_server_config(text, "c.toml"); });
  EXPECT_THAT(e, HasSubstr("c.toml:19:8: registers.setpoints[1].nmae = \"S\" (unknown key), "
                           "expected one of the known keys: name, address"));
}

TEST(ServerConfig, UnknownWordOrderIsNamed) {
  const std::string e = error_of([] { parse_server_config(two_by_two("", "BACD"), "c.toml"); });
  EXPECT_THAT(e, HasSubstr("registers.setpoints[0].word_order = \"BACD\", expected ABCD, CDAB, "
                           "BADC or DCBA"));
}

TEST(ServerConfig, OverlappingSetpointsAreRefused) {
  std::string text = two_by_two();
  text.replace(text.find("address = 102"), 13, "address = 101");
  const std::string e = error_of([&] { parse_server_config(text, "c.toml"); });
  EXPECT_THAT(e, HasSubstr("registers.setpoints[1].address = 101, expected no overlap with "
                           "registers.setpoints[0].address (registers 100..101)"));
}

TEST(ServerConfig, EchoOverlappingAValueInTheSameTableIsRefused) {
  std::string text = two_by_two();
  text.replace(text.find("heartbeat_echo_address = 10"), 27, "heartbeat_echo_address = 1");
  const std::string e = error_of([&] { parse_server_config(text); });
  EXPECT_THAT(e, HasSubstr("registers.heartbeat_echo_address = 1, expected no overlap with "
                           "registers.values[0].address (registers 0..1)"));
}

TEST(ServerConfig, Fc03ValueOverlappingASetpointIsRefused) {
  std::string text = two_by_two();
  text.replace(text.find("address = 0\nfunction_code = 4"), 29, "address = 103\nfunction_code = 3");
  const std::string e = error_of([&] { parse_server_config(text); });
  EXPECT_THAT(e, HasSubstr("registers.values[0].address = 103, expected no overlap with "
                           "registers.setpoints[1].address (registers 102..103)"));
}

TEST(ServerConfig, ControlBlockOverlappingTheHeartbeatIsRefused) {
  const std::string e =
      error_of([] { parse_server_config(two_by_two("control_address = 104\n")); });
  EXPECT_THAT(e, HasSubstr("registers.control_address = 104, expected no overlap with "
                           "registers.heartbeat_address (registers 104..104)"));
}

TEST(ServerConfig, SameAddressInDifferentTablesIsFine) {
  // Value 0 is an input register (FC04); a holding register 0 is a different register.
  EXPECT_NO_THROW(parse_server_config(two_by_two("control_address = 0\n")));
}

TEST(ServerConfig, ValueWithWriteFunctionCodeIsRefused) {
  std::string text = two_by_two();
  text.replace(text.find("function_code = 4\n\n[[registers.values]]"), 17, "function_code = 16");
  const std::string e = error_of([&] { parse_server_config(text); });
  EXPECT_THAT(e, HasSubstr("registers.values[0].function_code = 16, expected 3 (holding "
                           "registers) or 4 (input registers) for a value"));
}

TEST(ServerConfig, ValueWithoutFunctionCodeIsAHoldingRegisterAsInTheGateway) {
  // One register-map schema (hal/modbus/register_entry_toml.hpp): a value's function code
  // defaults to 3 on both sides of the link (this reader used to refuse the file).
  std::string text = two_by_two();
  text.replace(text.find("function_code = 4\n\n[[registers.values]]"), 17, "");
  const ServerConfig c = parse_server_config(text);
  EXPECT_EQ(c.registers.map.values[0].function_code, 3);
  EXPECT_EQ(c.registers.map.setpoints[0].function_code, 16);
}

TEST(ServerConfig, MissingHeartbeatIsNamed) {
  std::string text = two_by_two();
  text.replace(text.find("heartbeat_address = 104"), 23, "");
  const std::string e = error_of([&] { parse_server_config(text); });
  EXPECT_THAT(e, HasSubstr("registers.heartbeat_address = (missing)"));
}

TEST(ServerConfig, WrongTypesAreNamed) {
  std::string text = two_by_two();
  text.replace(text.find("sample_time_min = 1.0"), 21, "sample_time_min = \"1\"");
  EXPECT_THAT(error_of([&] { parse_server_config(text); }),
              HasSubstr("config:4:19: plant.sample_time_min = \"1\", expected a number"));
  text = two_by_two();
  text.replace(text.find("address = 100"), 13, "address = -1");
  EXPECT_THAT(error_of([&] { parse_server_config(text); }),
              HasSubstr("config:15:11: registers.setpoints[0].address = -1, expected a register "
                        "address 0..65535"));
}

TEST(ServerConfig, TomlSyntaxErrorNamesTheLine) {
  EXPECT_THAT(error_of([] { parse_server_config("[registers\n", "c.toml"); }),
              HasSubstr("c.toml:1:11: Error while parsing table header"));
}

TEST(ServerLayout, SetpointCountMustMatchThePlantInputs) {
  const ServerConfig config = parse_server_config(two_by_two(), "c.toml");
  const std::string e = error_of([&] { compile_layout(config, 3, 2, false, "c.toml"); });
  EXPECT_THAT(e, HasSubstr("c.toml: registers.setpoints = 2 entries, expected 3 (one per plant "
                           "input, in plant order)"));
}

TEST(ServerLayout, ValueCountMustMatchThePlantOutputs) {
  const ServerConfig config = parse_server_config(two_by_two());
  EXPECT_THAT(error_of([&] { compile_layout(config, 2, 4, false); }),
              HasSubstr("registers.values = 2 entries, expected 4 (one per plant output"));
}

TEST(ServerLayout, BaselineCountsMustMatchThePlant) {
  std::string text = two_by_two();
  text.replace(text.find("input_baseline = [1.95, 1.71]"), 29, "input_baseline = [1.95]");
  const ServerConfig config = parse_server_config(text);
  EXPECT_THAT(error_of([&] { compile_layout(config, 2, 2, false); }),
              HasSubstr("plant.input_baseline = 1 values, expected 2 (one per plant input)"));
}

TEST(ServerLayout, LockstepNeedsTheHeartbeatWrittenLast) {
  std::string text = two_by_two();
  text.replace(text.find("heartbeat_address = 104"), 23, "heartbeat_address = 98");
  const ServerConfig config = parse_server_config(text);
  EXPECT_NO_THROW(compile_layout(config, 2, 2, false));
  EXPECT_THAT(error_of([&] { compile_layout(config, 2, 2, true); }),
              HasSubstr("registers.heartbeat_address = 98, expected above every setpoint "
                        "register in lock-step mode"));
}

TEST(LoadPlant, UnknownLibraryPlantListsTheKnownOnes) {
  PlantSettings settings;
  settings.library = "alatiqi5x5";
  const std::string e = error_of([&] { load_plant(settings, ".", "c.toml"); });
  EXPECT_THAT(e, HasSubstr("c.toml: plant.library = \"alatiqi5x5\", expected one of alatiqi4x4"));
}

TEST(LoadPlant, RelativePlantFileIsReadFromTheConfigDirectory) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("excite-plant-unit-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "wb.toml") << library_plant_toml("woodberry2x2");
  PlantSettings settings;
  settings.file = "wb.toml";
  const auto plant = load_plant(settings, dir);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(plant->inputs(), 2);
  EXPECT_EQ(plant->static_gain(), library_plant("woodberry2x2").static_gain());
}

TEST(ServerConfig, LibraryAndFileTogetherAreRefused) {
  EXPECT_THAT(error_of([] {
                parse_server_config("[plant]\nlibrary = \"a\"\nfile = \"b\"\n" +
                                    two_by_two().substr(two_by_two().find("[registers]")));
              }),
              HasSubstr("plant.file = \"b\", expected either library or file, not both"));
}

TEST(LoadPlant, TheColumnsAreLivePlantsToo) {
  PlantSettings settings;
  for (const std::string name : {"colaA", "pilot15"}) {
    settings.library = name;
    EXPECT_EQ(load_plant(settings, ".")->inputs(), 2) << name;
  }
}

TEST(LoadPlant, NoPlantAtAllIsNamed) {
  EXPECT_THAT(error_of([] { load_plant(PlantSettings{}, ".", "c.toml"); }),
              HasSubstr("expected plant.library or plant.file"));
}

// The plant's own controller: the heartbeat watchdog and the input limits ([plant] keys).
std::string with_plant_keys(const std::string& keys) {
  std::string text = two_by_two();
  text.insert(text.find("[registers]"), keys + "\n");
  return text;
}

TEST(ServerConfig, WatchdogAndInputLimitsAreReadAndWrittenBack) {
  const ServerConfig c = parse_server_config(
      with_plant_keys("watchdog_s = 2.5\ninput_min = [0.0, -1.5]\ninput_max = [4.0, 3.25]"));
  EXPECT_EQ(c.plant.watchdog_s, 2.5);
  EXPECT_EQ(c.plant.input_min, (std::vector<double>{0.0, -1.5}));
  EXPECT_EQ(c.plant.input_max, (std::vector<double>{4.0, 3.25}));
  const ServerConfig back = parse_server_config(format_server_config(c));
  EXPECT_EQ(back.plant.watchdog_s, 2.5);
  EXPECT_EQ(back.plant.input_min, c.plant.input_min);
  EXPECT_EQ(back.plant.input_max, c.plant.input_max);
  EXPECT_EQ(parse_server_config(two_by_two()).plant.watchdog_s, 0.0) << "off by default";
  EXPECT_TRUE(parse_server_config(two_by_two()).plant.input_min.empty()) << "no limits";
}

TEST(ServerConfig, WatchdogNanOrNegativeIsRefusedByName) {
  EXPECT_THAT(error_of([] { parse_server_config(with_plant_keys("watchdog_s = nan")); }),
              HasSubstr("plant.watchdog_s = nan, expected a finite number"));
  EXPECT_THAT(
      error_of([] { parse_server_config(with_plant_keys("watchdog_s = -1.0")); }),
      HasSubstr("config:8:14: plant.watchdog_s = -1.0, expected >= 0 wall-clock seconds (0: off)"));
  EXPECT_THAT(error_of([] { parse_server_config(with_plant_keys("watchdog_s = \"3\"")); }),
              HasSubstr("plant.watchdog_s = \"3\", expected a number"));
}

TEST(ServerConfig, InputLimitsNanMismatchedOrInvertedAreRefusedByName) {
  EXPECT_THAT(
      error_of([] {
        parse_server_config(with_plant_keys("input_min = [nan, 0.0]\ninput_max = [1.0, 1.0]"));
      }),
      HasSubstr("plant.input_min[0] = nan, expected a finite number"));
  EXPECT_THAT(error_of([] {
                parse_server_config(with_plant_keys("input_min = [0.0, 0.0]\ninput_max = [1.0]"));
              }),
              HasSubstr("plant.input_max = (1 values), expected as many values as input_min (2)"));
  EXPECT_THAT(
      error_of([] {
        parse_server_config(with_plant_keys("input_min = [0.0, 2.0]\ninput_max = [1.0, -2.0]"));
      }),
      HasSubstr("plant.input_max[1] = -2, expected a limit above input_min[1] = 2"));
}

// Issue 42 §3: the offset limits (under a controller): each > 0, read and written back.
TEST(ServerConfig, OffsetLimitsAreReadAndANonPositiveOneIsRefusedByName) {
  const ServerConfig c =
      parse_server_config(with_plant_keys("offset_limit = [0.2, 0.2, 0.5, 0.5]"));
  EXPECT_EQ(c.plant.offset_limit, (std::vector<double>{0.2, 0.2, 0.5, 0.5}));
  EXPECT_THAT(error_of([] { parse_server_config(with_plant_keys("offset_limit = [0.2, 0.0]")); }),
              HasSubstr("plant.offset_limit[1] = 0, expected a bound > 0 on the size of that "
                        "test offset"));
  EXPECT_THAT(error_of([] { parse_server_config(with_plant_keys("offset_limit = [nan]")); }),
              HasSubstr("plant.offset_limit[0] = nan, expected a finite number"));
}

}  // namespace
}  // namespace excite::sim::server
