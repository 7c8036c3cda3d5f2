// SPDX-License-Identifier: MIT
// One message form across the rooms: the firmware core's Status, hal's configuration checks
// (config::Check) and the configuration reader all say "FIELD = VALUE, expected WHAT" (before, hal
// and the configuration readers said ": expected").
#include <gtest/gtest.h>

#include <string>

#include "base/config/check.hpp"
#include "base/config/document.hpp"
#include "base/config/error.hpp"
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

TEST(MessageForm, HalConfigurationCheck) {
  hal::modbus::ModbusConfig config;
  config.device.transport = "udp";
  expect_one_form(hal::modbus::validate(config).message(), "device.transport");
}

// A configuration check's result is config::Error's non-throwing form: the same three parts,
// the same message.
TEST(MessageForm, CheckIsTheErrorsNonThrowingForm) {
  const config::Check failed = config::Check::invalid("values[0].address", "65535", "0…65534");
  EXPECT_FALSE(failed.ok());
  EXPECT_EQ(failed.message(), "values[0].address = 65535, expected 0…65534");
  EXPECT_EQ(std::string(config::Error(failed).what()), failed.message());
  EXPECT_TRUE(config::Check::valid().ok());
  EXPECT_EQ(config::Check::valid().message(), "ok");
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
