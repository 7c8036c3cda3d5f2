// SPDX-License-Identifier: MIT
#include "firmware/app/register_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

namespace excite::app {

namespace {

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

CarriedRange sorted(double a, double b, double count, std::string what) {
  return {true, std::min(a, b), std::max(a, b), count, std::move(what)};
}

// Modbus: hal clamps a setpoint to [eng_min, eng_max] (= raw_min..raw_max); a value is
// converted from its raw reading without clamping, so the raw range's ends are the
// "end of the register's range" (a server clamps there too).
std::vector<CarriedRange> modbus_ranges(const std::vector<hal::modbus::Codec>& codecs,
                                        const std::vector<hal::modbus::RegisterEntry>& entries) {
  std::vector<CarriedRange> out;
  for (std::size_t i = 0; i < codecs.size(); ++i) {
    const hal::modbus::Codec& c = codecs[i];
    if (c.type == hal::modbus::RegisterType::float32) {
      out.push_back({});
      continue;
    }
    const double count = std::abs((c.eng_max - c.eng_min) / (c.raw_max - c.raw_min));
    out.push_back(sorted(c.eng_min, c.eng_max, count,
                         "register " + std::to_string(entries[i].address) + " " + entries[i].type +
                             " raw " + number_text(c.raw_min) + ".." + number_text(c.raw_max) +
                             " = " + number_text(c.eng_min) + ".." + number_text(c.eng_max)));
  }
  return out;
}

bool raw_limits(hal::can::SignalType type, double& lo, double& hi) {
  using T = hal::can::SignalType;
  switch (type) {
    case T::int8:
      lo = -128.0, hi = 127.0;
      return true;
    case T::uint8:
      lo = 0.0, hi = 255.0;
      return true;
    case T::int16:
      lo = -32768.0, hi = 32767.0;
      return true;
    case T::uint16:
      lo = 0.0, hi = 65535.0;
      return true;
    case T::int32:
      lo = -2147483648.0, hi = 2147483647.0;
      return true;
    case T::uint32:
      lo = 0.0, hi = 4294967295.0;
      return true;
    case T::float32:
      return false;
  }
  return false;
}

// CAN: engineering = raw · scale + offset, the raw type's whole range.
std::vector<CarriedRange> can_ranges(const std::vector<hal::can::SignalCodec>& codecs,
                                     const std::vector<hal::can::CanSignal>& signals) {
  std::vector<CarriedRange> out;
  for (std::size_t i = 0; i < codecs.size(); ++i) {
    const hal::can::SignalCodec& c = codecs[i];
    double lo = 0.0;
    double hi = 0.0;
    if (!raw_limits(c.type, lo, hi)) {
      out.push_back({});
      continue;
    }
    char id[16];
    std::snprintf(id, sizeof id, "0x%X", static_cast<unsigned>(signals[i].id));
    out.push_back(sorted(lo * c.scale + c.offset_eng, hi * c.scale + c.offset_eng,
                         std::abs(c.scale),
                         std::string("CAN ") + id + " " + signals[i].type + " scale " +
                             number_text(c.scale) + " offset " + number_text(c.offset_eng)));
  }
  return out;
}

}  // namespace

std::vector<CarriedRange> setpoint_ranges(const GatewayConfig& config) {
  if (config.transport == Transport::can) {
    hal::can::CanPlan plan;
    if (!hal::can::compile_frame_map(config.can.map, plan).ok()) return {};
    return can_ranges(plan.setpoints, config.can.map.setpoints);
  }
  hal::modbus::RegisterPlan plan;
  if (!hal::modbus::compile_register_map(config.modbus.map, plan).ok()) return {};
  return modbus_ranges(plan.setpoints, config.modbus.map.setpoints);
}

std::vector<CarriedRange> value_ranges(const GatewayConfig& config) {
  if (config.transport == Transport::can) {
    hal::can::CanPlan plan;
    if (!hal::can::compile_frame_map(config.can.map, plan).ok()) return {};
    return can_ranges(plan.values, config.can.map.values);
  }
  hal::modbus::RegisterPlan plan;
  if (!hal::modbus::compile_register_map(config.modbus.map, plan).ok()) return {};
  return modbus_ranges(plan.values, config.modbus.map.values);
}

}  // namespace excite::app
