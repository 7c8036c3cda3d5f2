// SPDX-License-Identifier: MIT
// The configuration room: every refusal reads "FILE:LINE:COL: FIELD = VALUE, expected …".
#include "base/config/table.hpp"
#include "base/config/document.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace excite::config {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// The message of the config::Error `read` throws on `text` (parsed as "c.toml").
std::string error_of(std::string_view text, const std::function<void(const Table&)>& read) {
  const toml::table root = parse(text, "c.toml");
  try {
    read(Table(root, "", "c.toml"));
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ConfigMessage, OneFormWithPosition) {
  EXPECT_EQ(format_message("f.toml", {3, 7}, "a.b", "2", "an integer 0..1"),
            "f.toml:3:7: a.b = 2, expected an integer 0..1");
  EXPECT_EQ(format_message("f.toml", {}, "a.b", "2", "x"), "f.toml: a.b = 2, expected x");
  EXPECT_EQ(format_message("", {}, "a.b", "2", "x"), "a.b = 2, expected x");
}

TEST(ConfigMessage, WithSourceNamesTheFileOnce) {
  const Error e("values[0].role", "\"x\"", "output");
  EXPECT_STREQ(e.what(), "values[0].role = \"x\", expected output");
  EXPECT_STREQ(e.with_source("g.toml").what(), "g.toml: values[0].role = \"x\", expected output");
  const Error placed("a.toml", {1, 1}, "k", "1", "2");
  EXPECT_STREQ(placed.with_source("other").what(), "a.toml:1:1: k = 1, expected 2");
}

TEST(ConfigParse, SyntaxErrorNamesFileLineColumn) {
  try {
    (void)parse("a = 1\nb = = 2\n", "s.toml");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), StartsWith("s.toml:2:")) << e.what();
  }
}

TEST(ConfigParse, UnreadableFileNamesIt) {
  try {
    (void)read_file("/nonexistent/x.toml");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), StartsWith("/nonexistent/x.toml: cannot be read")) << e.what();
  }
}

TEST(ConfigParse, ReadsAFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("excite_config_test_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(path) << "a = 1\n";
  const std::string text = read_file(path);
  std::filesystem::remove(path);
  EXPECT_EQ(text, "a = 1\n");
}

TEST(ConfigKeys, UnknownKeyIsNamedWithTheKnownOnes) {
  const std::string e = error_of("[plant]\nlibary = \"x\"\n", [](const Table& t) {
    t.required_table("plant").only_keys({"library", "file"});
  });
  EXPECT_EQ(e,
            "c.toml:2:10: plant.libary = \"x\" (unknown key), expected one of the known keys: "
            "library, file");
}

TEST(ConfigGetters, WrongTypeNamesFieldValueAndPosition) {
  EXPECT_EQ(error_of("x = \"1\"\n", [](const Table& t) { (void)t.number("x"); }),
            "c.toml:1:5: x = \"1\", expected a number");
  EXPECT_EQ(error_of("x = 1\n", [](const Table& t) { (void)t.text("x"); }),
            "c.toml:1:5: x = 1, expected a string");
  EXPECT_EQ(error_of("x = 1\n", [](const Table& t) { (void)t.flag("x"); }),
            "c.toml:1:5: x = 1, expected true or false");
  EXPECT_EQ(error_of("x = 1\n", [](const Table& t) { (void)t.table("x"); }),
            "c.toml:1:5: x = 1, expected a table [x]");
}

TEST(ConfigGetters, MissingKeyIsNamed) {
  EXPECT_THAT(error_of("[t]\na = 1\n",
                       [](const Table& t) { (void)t.required_table("t").required_number("b"); }),
              HasSubstr("t.b = (missing), expected a number"));
  EXPECT_THAT(error_of("", [](const Table& t) { (void)t.required_table("t"); }),
              HasSubstr("c.toml: t = (missing), expected a table"));
}

TEST(ConfigRanges, NumbersMustBeFinite) {
  EXPECT_EQ(error_of("x = nan\n", [](const Table& t) { (void)t.number("x"); }),
            "c.toml:1:5: x = nan, expected a finite number");
  EXPECT_EQ(error_of("x = -inf\n", [](const Table& t) { (void)t.positive("x"); }),
            "c.toml:1:5: x = -inf, expected a finite number");
}

TEST(ConfigRanges, PositiveAndNonNegativeNameTheUnit) {
  EXPECT_EQ(error_of("x = 0\n", [](const Table& t) { (void)t.positive("x", "minutes"); }),
            "c.toml:1:5: x = 0, expected > 0 minutes");
  EXPECT_EQ(error_of("x = -0.5\n", [](const Table& t) { (void)t.non_negative("x", "s"); }),
            "c.toml:1:5: x = -0.5, expected >= 0 s");
  const toml::table root = parse("x = 0\ny = 2.5\n", "c.toml");
  const Table t(root, "", "c.toml");
  EXPECT_EQ(*t.non_negative("x"), 0.0);
  EXPECT_EQ(*t.positive("y"), 2.5);
  EXPECT_FALSE(t.positive("z").has_value());
}

TEST(ConfigRanges, IntegersAreExactAndInRange) {
  EXPECT_EQ(error_of("n = 70000\n", [](const Table& t) { (void)t.integer("n", 0, 65535); }),
            "c.toml:1:5: n = 70000, expected an integer 0..65535");
  EXPECT_EQ(error_of("n = 3.0\n", [](const Table& t) { (void)t.integer("n", 0, 9); }),
            "c.toml:1:5: n = 3.0, expected an integer 0..9");
  // The largest TOML integer compares without overflow.
  EXPECT_EQ(error_of("n = 9223372036854775807\n",
                     [](const Table& t) { (void)t.integer("n", 0, 4294967295, "a seed"); }),
            "c.toml:1:5: n = 9223372036854775807, expected a seed");
  const toml::table root = parse("n = -32768\n", "c.toml");
  EXPECT_EQ(*Table(root, "", "c.toml").integer("n", -32768, 65535), -32768);
}

TEST(ConfigArrays, ElementsAreNamedByIndex) {
  EXPECT_EQ(error_of("v = [1, \"2\"]\n", [](const Table& t) { (void)t.numbers("v"); }),
            "c.toml:1:9: v[1] = \"2\", expected a number");
  EXPECT_EQ(error_of("v = [\"a\", 2]\n", [](const Table& t) { (void)t.texts("v"); }),
            "c.toml:1:11: v[1] = 2, expected a string");
  const toml::table root = parse("v = 0.5\n", "c.toml");
  EXPECT_EQ(Table(root, "", "c.toml").numbers("v", true), std::vector<double>{0.5});
}

TEST(ConfigArrays, ArrayOfTablesNamesEachEntry) {
  const std::string e = error_of("[[s]]\naddress = 1\n[[s]]\nadress = 2\n", [](const Table& t) {
    for (const Table& s : t.tables("s")) s.only_keys({"address"});
  });
  EXPECT_THAT(e, StartsWith("c.toml:4:10: s[1].adress = 2 (unknown key), expected one of"));
}

TEST(ConfigChoices, ListsTheChoices) {
  EXPECT_EQ(error_of("m = \"x\"\n",
                     [](const Table& t) {
                       (void)t.choice("m", {"hold", "ramp", "stop"});
                     }),
            "c.toml:1:5: m = \"x\", expected \"hold\", \"ramp\" or \"stop\"");
}

}  // namespace
}  // namespace excite::config
