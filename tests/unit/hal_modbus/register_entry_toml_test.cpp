// SPDX-License-Identifier: MIT
// The register-map schema both configuration files use: defaults and refusals in one place.
#include "hal/modbus/register_entry_toml.hpp"

#include <gtest/gtest.h>

#include <string>

#include "base/config/document.hpp"

namespace excite::hal::modbus {
namespace {

RegisterEntry entry(std::string_view text, EntryKind kind) {
  const toml::table doc = config::parse(text, "m.toml");
  return read_register_entry(config::Table(doc, "values[0]", "m.toml"), kind);
}

std::string error_of(std::string_view text) {
  try {
    (void)entry(text, EntryKind::value);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RegisterEntryToml, DefaultsAreTheSameForEveryReader) {
  const RegisterEntry s = entry("address = 10\n", EntryKind::setpoint);
  EXPECT_EQ(s.address, 10u);
  EXPECT_EQ(s.function_code, 16);
  EXPECT_EQ(s.type, "float32");
  EXPECT_EQ(s.word_order, "ABCD");
  EXPECT_FALSE(s.raw_min.has_value());
  const RegisterEntry v = entry("address = 0\n", EntryKind::value);
  EXPECT_EQ(v.function_code, 3);  // holding registers, where a setpoint's readback is
}

TEST(RegisterEntryToml, ReadsEveryField) {
  const RegisterEntry v = entry(
      "address = 7\nfunction_code = 4\ntype = \"int16\"\nword_order = \"CDAB\"\n"
      "eng_min = -5\neng_max = 5.5\nraw_min = -32768\nraw_max = 32767\n",
      EntryKind::value);
  EXPECT_EQ(v.address, 7u);
  EXPECT_EQ(v.function_code, 4);
  EXPECT_EQ(v.type, "int16");
  EXPECT_EQ(v.word_order, "CDAB");
  EXPECT_EQ(v.eng_min, -5.0);
  EXPECT_EQ(v.eng_max, 5.5);
  EXPECT_EQ(v.raw_min, -32768);
  EXPECT_EQ(v.raw_max, 32767);
}

// The writer beside the reader: what format_register_entry writes, read_register_entry
// reads back into the same fields, for each kind of register.
void expect_round_trip(const RegisterEntry& e, EntryKind kind) {
  const RegisterEntry back = entry(format_register_entry(e, kind), kind);
  EXPECT_EQ(back.address, e.address);
  EXPECT_EQ(back.function_code, e.function_code);
  EXPECT_EQ(back.type, e.type);
  if (e.type == "float32") {
    EXPECT_EQ(back.word_order, e.word_order);
  } else {
    EXPECT_EQ(back.eng_min, e.eng_min);
    EXPECT_EQ(back.eng_max, e.eng_max);
    EXPECT_EQ(back.raw_min, e.raw_min);
    EXPECT_EQ(back.raw_max, e.raw_max);
  }
}

TEST(RegisterEntryToml, WhatTheWriterWritesTheReaderReadsBack) {
  RegisterEntry setpoint;
  setpoint.address = 100;
  setpoint.word_order = "CDAB";
  expect_round_trip(setpoint, EntryKind::setpoint);
  EXPECT_EQ(format_register_entry(setpoint, EntryKind::setpoint),
            "address = 100\ntype = \"float32\"\nword_order = \"CDAB\"\n");  // FC16 implied

  RegisterEntry scaled;
  scaled.address = 7;
  scaled.function_code = 4;
  scaled.type = "int16";
  scaled.eng_min = -5.0;
  scaled.eng_max = 0.1;  // not a short decimal in binary: written so it reads back exactly
  scaled.raw_min = -1000;
  scaled.raw_max = 1000;
  expect_round_trip(scaled, EntryKind::value);

  RegisterEntry counter;
  counter.address = 300;
  counter.function_code = 3;
  counter.type = "uint16";
  counter.eng_max = 65535.0;
  expect_round_trip(counter, EntryKind::value);
  EXPECT_EQ(format_register_entry(counter, EntryKind::value),
            "address = 300\nfunction_code = 3\ntype = \"uint16\"\neng_min = 0.0\n"
            "eng_max = 65535.0\n");

  RegisterEntry odd_setpoint = setpoint;  // a setpoint code other than 16 is not dropped
  odd_setpoint.function_code = 6;
  expect_round_trip(odd_setpoint, EntryKind::setpoint);
}

TEST(RegisterEntryToml, MapSettingsRoundTrip) {
  RegisterMap map;
  map.heartbeat_address = 108;
  map.write_chunk = 10;
  map.read_chunk = 20;
  const std::string text = format_map_settings(map);
  const toml::table doc = config::parse(text, "m.toml");
  RegisterMap back;
  read_map_settings(config::Table(doc, "map", "m.toml"), back);
  EXPECT_EQ(back.heartbeat_address, map.heartbeat_address);
  EXPECT_EQ(back.write_chunk, 10u);
  EXPECT_EQ(back.read_chunk, 20u);
}

TEST(RegisterEntryToml, RefusalsNameFieldValueAndPosition) {
  EXPECT_EQ(error_of("type = \"int16\"\n"),
            "m.toml:1:1: values[0].address = (missing), expected a register address 0..65535");
  EXPECT_EQ(error_of("address = 65536\n"),
            "m.toml:1:11: values[0].address = 65536, expected a register address 0..65535");
  EXPECT_EQ(error_of("address = 1\nraw_max = 70000\n"),
            "m.toml:2:11: values[0].raw_max = 70000, expected an integer -32768..65535");
  EXPECT_EQ(error_of("address = 1\neng_min = nan\n"),
            "m.toml:2:11: values[0].eng_min = nan, expected a finite number");
}

TEST(RegisterEntryToml, MapSettingsKeepWhatIsAbsent) {
  const toml::table doc = config::parse("write_chunk = 60\n", "m.toml");
  RegisterMap map;
  read_map_settings(config::Table(doc, "map", "m.toml"), map);
  EXPECT_EQ(map.write_chunk, 60u);
  EXPECT_EQ(map.read_chunk, max_read_registers);
  EXPECT_FALSE(map.heartbeat_address.has_value());
  const toml::table bad = config::parse("read_chunk = 126\n", "m.toml");
  EXPECT_THROW(read_map_settings(config::Table(bad, "map", "m.toml"), map), config::Error);
}

}  // namespace
}  // namespace excite::hal::modbus
