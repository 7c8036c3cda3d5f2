// SPDX-License-Identifier: MIT
// One message form across the rooms: the firmware core's Status, hal's Validation and the
// configuration reader all say "FIELD = VALUE, expected WHAT" (before, hal and the
// configuration readers said ": expected").
#include <gtest/gtest.h>

#include <string>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "firmware/signal/validate.hpp"
#include "hal/modbus/modbus_field_bus.hpp"

namespace excite {
namespace {

void expect_one_form(const std::string& message, const std::string& field) {
  EXPECT_NE(message.find(field + " = "), std::string::npos) << message;
  EXPECT_NE(message.find(", expected "), std::string::npos) << message;
  EXPECT_EQ(message.find(": expected"), std::string::npos) << message;
}

TEST(MessageForm, FirmwareSignal) {
  signal::Recipe recipe;
  recipe.channels = 0;
  const signal::Status s = signal::validate(recipe, 16);
  ASSERT_FALSE(s);
  expect_one_form(s.message(), "channels");
}

TEST(MessageForm, HalValidation) {
  hal::modbus::ModbusConfig config;
  config.device.transport = "udp";
  expect_one_form(hal::modbus::validate(config).message(), "device.transport");
}

TEST(MessageForm, ConfigurationFiles) {
  const toml::table doc = config::parse("n = 70000\n", "c.toml");
  try {
    (void)config::Table(doc, "map", "c.toml").integer("n", 0, 65535);
    FAIL() << "no error";
  } catch (const config::Error& e) {
    expect_one_form(e.what(), "map.n");
  }
}

}  // namespace
}  // namespace excite
