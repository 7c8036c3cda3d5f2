// SPDX-License-Identifier: MIT
#pragma once
// The table of field-bus transports by the name [device] transport gives (libmodbus's
// backend table, one level up): each row builds a transport's configuration
// (excite/hal/transport.hpp), which then reads its own part of the file. The gateway looks a
// name up here and never names a transport itself; a new transport is a new folder beside
// hal/modbus and hal/can plus its row in transports.cpp.

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/config/check.hpp"
#include "excite/hal/transport.hpp"

namespace excite::hal {

struct TransportEntry {
  std::string_view name;   // canonical, e.g. "modbus-tcp"
  std::string_view alias;  // an older name still accepted ("" for none)
  std::unique_ptr<TransportConfig> (*make)();
};

/// Every transport, the default (used when [device] has no transport key) first.
std::span<const TransportEntry> transports() noexcept;

/// The transport called `name` (canonical or alias), or null.
const TransportEntry* find_transport(std::string_view name) noexcept;

/// What a [device] transport may be, for messages: "\"modbus-tcp\", … or \"can\" (\"tcp\"
/// and \"rtu\" are still accepted)".
std::string transport_choices();

/// The root sections of every transport (TransportConfig::sections()), each once, sorted.
std::vector<std::string> transport_sections();

/// Whether the limits [min, max] of the setpoint at `where` ("setpoints[2]") lie inside what
/// its encoding carries; else names where.min or where.max, the limit (config::format_number:
/// the shortest text that reads back to the same double) and the end of
/// `range` ("<= 2, the most register 104 int16 raw 0..27648 = 0..2 can carry").
config::Check check_carried(const CarriedRange& range, const std::string& where, double min,
                            double max);

}  // namespace excite::hal
