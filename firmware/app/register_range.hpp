// SPDX-License-Identifier: MIT
#pragma once
// What the field encoding of each setpoint and value can carry, in engineering units
// (start-up only, allocates). A scaled int16/uint16 register (Modbus) or an integer CAN
// signal carries a bounded range; float32 is treated as unbounded.
//   - setpoints: the configured limits [min, max] must lie inside the carried range, else
//     the configuration is refused (a setpoint the register cannot hold would be clipped
//     silently by the bus);
//   - values: a reading at the end of its register's range (within a quarter of one raw
//     count of the end, or beyond) may be a clipped value; the Runner counts such readings
//     per value and the gateway reports them at the end of the run.

#include <string>
#include <vector>

#include "firmware/app/gateway_config.hpp"

namespace excite::app {

struct CarriedRange {
  bool bounded = false;  // false: float32, nothing to check
  double low = 0.0;      // engineering units at the low end of the encoding
  double high = 0.0;     // … and at the high end (low ≤ high)
  double count = 0.0;    // engineering units per raw count (> 0 when bounded)
  std::string what;      // "register 104 int16 raw 0..27648" / "CAN 0x210 int16 scale 0.1"
};

/// Per setpoint, in configuration order.
std::vector<CarriedRange> setpoint_ranges(const GatewayConfig& config);

/// Per value, in configuration order.
std::vector<CarriedRange> value_ranges(const GatewayConfig& config);

}  // namespace excite::app
