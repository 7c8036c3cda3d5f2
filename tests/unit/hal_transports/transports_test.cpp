// SPDX-License-Identifier: MIT
// The transport seam: the table finds each transport by its name, and each transport reads
// its own part of a configuration and describes its peer, channels and carried ranges.
#include "hal/transports/transports.hpp"

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "base/config/document.hpp"
#include "base/config/table.hpp"

namespace excite::hal {
namespace {

// Reads `text` ([device], the transport's sections, one setpoint and one value entry) into
// the transport called `name`, in the order the gateway's reader calls it.
std::unique_ptr<TransportConfig> read(std::string_view name, std::string_view text) {
  const TransportEntry* entry = find_transport(name);
  EXPECT_NE(entry, nullptr) << name;
  std::unique_ptr<TransportConfig> t = entry->make();
  const toml::table doc = config::parse(text, "t.toml");
  const config::Table root(doc, "", "t.toml");
  if (auto device = root.table("device")) t->read_device(*device);
  t->read_sections(root);
  t->read_entry(*root.table("setpoint"), ChannelKind::setpoint, "u1");
  t->read_entry(*root.table("value"), ChannelKind::value, "u1_rb");
  t->validate();
  return t;
}

TEST(Transports, EachIsFoundByItsNameOrItsOlderName) {
  ASSERT_FALSE(transports().empty());
  EXPECT_EQ(transports().front().name, "modbus-tcp");  // the default
  for (const TransportEntry& t : transports()) {
    EXPECT_EQ(find_transport(t.name)->make()->name(), t.name);
  }
  EXPECT_EQ(find_transport("tcp")->name, "modbus-tcp");
  EXPECT_EQ(find_transport("rtu")->name, "modbus-rtu");
  EXPECT_EQ(find_transport("udp"), nullptr);
  EXPECT_EQ(transport_choices(),
            "\"modbus-tcp\", \"modbus-rtu\" or \"can\" (\"tcp\" and \"rtu\" are still accepted)");
  EXPECT_EQ(transport_sections(), (std::vector<std::string>{"can", "map"}));
}

TEST(Transports, ModbusDescribesItsPeerRegistersAndRanges) {
  const auto t = read("modbus-tcp",
                      "[device]\nhost = \"10.0.0.5\"\nresponse_timeout_ms = 200\n"
                      "[map]\nheartbeat_address = 120\n"
                      "[setpoint]\naddress = 100\ntype = \"int16\"\neng_min = 0\neng_max = 2\n"
                      "raw_min = 0\nraw_max = 27648\n"
                      "[value]\naddress = 200\nfunction_code = 4\n");
  EXPECT_EQ(t->describe_peer(), "modbus-tcp 10.0.0.5:502 unit 1, response timeout 200 ms");
  EXPECT_EQ(t->describe_channel(ChannelKind::setpoint, 0), "register 100 int16");
  EXPECT_EQ(t->describe_channel(ChannelKind::value, 0), "register 200 float32 ABCD");
  EXPECT_EQ(t->channel_columns(ChannelKind::value, 0), "register   200 FC04 float32");
  EXPECT_EQ(t->heartbeat_columns(), "register   120 uint16");
  EXPECT_DOUBLE_EQ(t->response_timeout_s(), 0.2);
  const std::vector<CarriedRange> sp = t->carried_range(ChannelKind::setpoint);
  ASSERT_EQ(sp.size(), 1U);
  EXPECT_TRUE(sp[0].bounded);
  EXPECT_EQ(sp[0].high, 2.0);
  EXPECT_EQ(sp[0].what, "register 100 int16 raw 0..27648 = 0..2");
  EXPECT_FALSE(t->carried_range(ChannelKind::value)[0].bounded);  // float32
}

TEST(Transports, CanDescribesItsInterfaceFramesAndRanges) {
  const auto t = read("can",
                      "[can]\ninterface = \"vcan0\"\nbitrate = 500000\nvalue_timeout_ms = 50\n"
                      "[setpoint]\ncan_id = 0x210\ntype = \"int16\"\nscale = 0.001\n"
                      "[value]\ncan_id = 0x310\nbyte_offset = 4\ntype = \"float32\"\n");
  EXPECT_EQ(t->describe_peer(), "can vcan0 500000 bit/s, value frames stale after 50 ms");
  EXPECT_EQ(t->describe_channel(ChannelKind::setpoint, 0), "CAN 0x210 byte 0 int16");
  EXPECT_EQ(t->heartbeat_columns(), "");
  EXPECT_DOUBLE_EQ(t->response_timeout_s(), 0.05);
  const std::vector<CarriedRange> sp = t->carried_range(ChannelKind::setpoint);
  ASSERT_EQ(sp.size(), 1U);
  EXPECT_DOUBLE_EQ(sp[0].high, 32.767);
  EXPECT_EQ(sp[0].what, "CAN 0x210 int16 scale 0.001 offset 0");
  EXPECT_EQ(t->check_tick(1.0), "");  // two frames a second at 500 kbit/s
}

TEST(Transports, EachRefusesTheOthersKeysItsOwnWay) {
  EXPECT_THROW((void)read("can", "[setpoint]\ncan_id = 0x210\n[value]\ncan_id = 0x310\n"),
               config::Error);  // no [can]
  try {
    (void)read("can",
               "[can]\ninterface = \"can0\"\n[map]\nheartbeat_address = 1\n"
               "[setpoint]\ncan_id = 0x210\n[value]\ncan_id = 0x310\n");
    ADD_FAILURE() << "a [map] under can was accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("the heartbeat is can.heartbeat_id"), std::string::npos)
        << e.what();
  }
}

TEST(Transports, LimitsOutsideTheCarriedRangeAreNamed) {
  const CarriedRange r{true, 0.0, 2.0, 2.0 / 27648, "register 104 int16 raw 0..27648 = 0..2"};
  EXPECT_TRUE(check_carried(r, "setpoints[2]", 0.0, 2.0).ok());
  EXPECT_EQ(check_carried(r, "setpoints[2]", 0.0, 2.5).message(),
            "setpoints[2].max = 2.5, expected <= 2, the most register 104 int16 raw 0..27648 = "
            "0..2 can carry");
  EXPECT_EQ(check_carried(r, "setpoints[2]", -0.5, 1.0).field, "setpoints[2].min");
  EXPECT_TRUE(check_carried(CarriedRange{}, "setpoints[0]", -1e30, 1e30).ok());  // float32
}

}  // namespace
}  // namespace excite::hal
