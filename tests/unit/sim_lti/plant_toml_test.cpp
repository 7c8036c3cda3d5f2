// SPDX-License-Identifier: MIT
// Plant files: TOML with the element grammar; errors name the key or the row/column.
#include "sim/lti/plant_toml.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace excite::sim {
namespace {

std::string error_of(std::string_view toml) {
  try {
    (void)plant_from_toml(toml, "test.toml");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

constexpr std::string_view kTwoByTwo = R"toml(
name = "demo"
description = "a 2x2 plant"
time_unit = "min"
inputs = ["reflux", "boilup"]
outputs = ["xD", "xB"]
G = [
  ["12.8 e^-1s / (16.7s+1)", -18.9],
  ["6.6 e^-7s / (10.9s+1)",  "87.8/(194s+1) + 1.4/(15s+1)"],
]
)toml";

TEST(PlantToml, ReadsNamesAndElements) {
  const PlantDefinition def = plant_from_toml(kTwoByTwo);
  EXPECT_EQ(def.name, "demo");
  EXPECT_EQ(def.description, "a 2x2 plant");
  EXPECT_EQ(def.g.inputs(), 2);
  EXPECT_EQ(def.g.outputs(), 2);
  EXPECT_EQ(def.g.input_names(), (std::vector<std::string>{"reflux", "boilup"}));
  EXPECT_EQ(def.g.output_names(), (std::vector<std::string>{"xD", "xB"}));
  const Eigen::MatrixXd g0 = def.g.static_gain();
  EXPECT_DOUBLE_EQ(g0(0, 0), 12.8);
  EXPECT_DOUBLE_EQ(g0(0, 1), -18.9);  // a bare number is a static gain
  EXPECT_DOUBLE_EQ(g0(1, 0), 6.6);
  EXPECT_DOUBLE_EQ(g0(1, 1), 89.2);
}

TEST(PlantToml, LoadsFromAFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("excite_plant_toml_test_" + std::to_string(::getpid()) + ".toml");
  {
    std::ofstream out(path);
    out << kTwoByTwo;
  }
  const PlantDefinition def = load_plant_file(path);
  std::filesystem::remove(path);
  EXPECT_EQ(def.name, "demo");
  EXPECT_DOUBLE_EQ(def.g.static_gain()(1, 0), 6.6);
}

TEST(PlantToml, MissingFileIsAnError) {
  EXPECT_THROW((void)load_plant_file("/nonexistent/plant.toml"), std::invalid_argument);
}

TEST(PlantTomlErrors, BadElementNamesRowColumnTextAndPosition) {
  const std::string what = error_of(R"toml(
outputs = ["xD", "xB"]
G = [["1/(s+1)", "2/(s+1"], ["0", "0"]]
)toml");
  EXPECT_NE(what.find("test.toml"), std::string::npos) << what;
  EXPECT_NE(what.find("row 1 (xD), column 2 (u2)"), std::string::npos) << what;
  EXPECT_NE(what.find("\"2/(s+1\""), std::string::npos) << what;
  EXPECT_NE(what.find("position 7"), std::string::npos) << what;
}

TEST(PlantTomlErrors, RaggedRows) {
  EXPECT_NE(error_of(R"toml(G = [["1", "2"], ["3"]])toml").find("row 2: 1 elements, expected 2"),
            std::string::npos);
}

TEST(PlantTomlErrors, UnknownKey) {
  EXPECT_EQ(error_of("G = [[\"1\"]]\nsampel_time = 1\n"),
            "test.toml:2:15: sampel_time = 1 (unknown key), expected one of the known keys: name, "
            "description, time_unit, inputs, outputs, allow_unstable, G");
}

TEST(PlantTomlErrors, WrongTimeUnit) {
  EXPECT_EQ(error_of("G = [[\"1\"]]\ntime_unit = \"s\"\n"),
            "test.toml:2:13: time_unit = \"s\", expected \"min\" (all times are in minutes)");
}

TEST(PlantTomlErrors, NameCountMustMatch) {
  EXPECT_NE(error_of("G = [[\"1\", \"2\"]]\ninputs = [\"a\"]\n")
                .find("inputs: 1 names given, expected 2"),
            std::string::npos);
  EXPECT_NE(error_of("G = [[\"1\", \"2\"]]\ninputs = [\"a\", \"a\"]\n").find("unique"),
            std::string::npos);
}

TEST(PlantTomlErrors, MissingMatrixAndTomlSyntax) {
  EXPECT_EQ(error_of("name = \"x\"\n"),
            "test.toml: G = (missing), expected an array of rows of element strings");
  EXPECT_EQ(error_of("G = [[\"1\"]\n").rfind("test.toml:1:", 0), 0u);
  EXPECT_EQ(error_of("G = [[\"1\"], [true]]\n"),
            "test.toml:1:14: G[1][0] = true, expected an element string such as \"4.09 "
            "e^-1.3s / (33s+1)\"");
  EXPECT_EQ(error_of("G = [[\"1\"]]\ninputs = \"u\"\n"),
            "test.toml:2:10: inputs = \"u\", expected an array of strings");
}

TEST(PlantToml, UnstableElementsNeedTheFlag) {
  EXPECT_NE(error_of("G = [[\"1/(-3s+1)\"]]\n").find("allow_unstable"), std::string::npos);
  const PlantDefinition def = plant_from_toml("allow_unstable = true\nG = [[\"1/(-3s+1)\"]]\n");
  EXPECT_DOUBLE_EQ(def.g.static_gain()(0, 0), 1.0);
}

}  // namespace
}  // namespace excite::sim
