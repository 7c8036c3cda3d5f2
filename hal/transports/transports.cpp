// SPDX-License-Identifier: MIT
#include "hal/transports/transports.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "base/config/document.hpp"
#include "hal/can/can_transport.hpp"
#include "hal/modbus/modbus_transport.hpp"

namespace excite::hal {

namespace {

const std::array<TransportEntry, 3> kTransports = {{
    {"modbus-tcp", "tcp", [] { return modbus::make_transport_config("modbus-tcp"); }},
    {"modbus-rtu", "rtu", [] { return modbus::make_transport_config("modbus-rtu"); }},
    {"can", "", [] { return can::make_transport_config(); }},
}};

}  // namespace

std::span<const TransportEntry> transports() noexcept {
  return kTransports;
}

const TransportEntry* find_transport(std::string_view name) noexcept {
  for (const TransportEntry& t : kTransports) {
    if (name == t.name || (!t.alias.empty() && name == t.alias)) return &t;
  }
  return nullptr;
}

std::string transport_choices() {
  std::string names;
  std::vector<std::string> aliases;
  for (std::size_t i = 0; i < kTransports.size(); ++i) {
    names += (i == 0                        ? ""
              : i + 1 == kTransports.size() ? " or "
                                            : ", ") +
             std::string("\"") + std::string(kTransports[i].name) + "\"";
    if (!kTransports[i].alias.empty())
      aliases.push_back('"' + std::string(kTransports[i].alias) + '"');
  }
  if (aliases.empty()) return names;
  std::string old;
  for (std::size_t i = 0; i < aliases.size(); ++i) {
    old += (i == 0 ? "" : i + 1 == aliases.size() ? " and " : ", ") + aliases[i];
  }
  return names + " (" + old + (aliases.size() == 1 ? " is" : " are") + " still accepted)";
}

std::vector<std::string> transport_sections() {
  std::vector<std::string> out;
  for (const TransportEntry& t : kTransports) {
    for (std::string& s : t.make()->sections()) out.push_back(std::move(s));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

namespace {}  // namespace

config::Check check_carried(const CarriedRange& range, const std::string& where, double min,
                            double max) {
  if (!range.bounded) return config::Check::valid();
  if (min < range.low) {
    return config::Check::invalid(
        where + ".min", config::format_number(min),
        ">= " + config::format_number(range.low) + ", the least " + range.what + " can carry");
  }
  if (max > range.high) {
    return config::Check::invalid(
        where + ".max", config::format_number(max),
        "<= " + config::format_number(range.high) + ", the most " + range.what + " can carry");
  }
  return config::Check::valid();
}

}  // namespace excite::hal
