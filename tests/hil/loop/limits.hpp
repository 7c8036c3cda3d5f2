// SPDX-License-Identifier: MIT
#pragma once
// The setpoint limits a loop test configured (gateway.toml, [[setpoints]] min/max as
// `excite loop-config` writes them) and the plant-side check against them: what the plant
// received (its own run log, absolute u) never left [min, max].

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"

namespace excite::test {

struct SetpointLimits {
  std::string name;
  double min = NAN;
  double max = NAN;
};

/// Every [[setpoints]] table's name, min and max of `gateway_toml`, in order (the
/// `key = value` lines loop-config writes; a missing min or max stays NaN and fails below).
inline std::vector<SetpointLimits> configured_limits(const std::filesystem::path& gateway_toml) {
  std::vector<SetpointLimits> limits;
  std::ifstream in(gateway_toml);
  bool in_setpoint = false;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '[') {
      in_setpoint = line == "[[setpoints]]";
      if (in_setpoint) limits.emplace_back();
      continue;
    }
    if (!in_setpoint) continue;
    const auto eq = line.find(" = ");
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq);
    const std::string value = line.substr(eq + 3);
    if (key == "name") limits.back().name = value.substr(1, value.size() - 2);
    if (key == "min") limits.back().min = std::stod(value);
    if (key == "max") limits.back().max = std::stod(value);
  }
  return limits;
}

/// Asserts every u the plant received is inside [min, max] widened by the float32 register's
/// rounding (|u|·2⁻²³), with the inputs in the configuration's order.
inline void expect_plant_inside_configured_limits(const runlog::RunLog& plant,
                                                  const std::vector<SetpointLimits>& limits) {
  ASSERT_EQ(plant.u.size(), limits.size()) << "inputs in the plant log against [[setpoints]]";
  for (std::size_t i = 0; i < limits.size(); ++i) {
    ASSERT_TRUE(std::isfinite(limits[i].min) && std::isfinite(limits[i].max)) << limits[i].name;
    const auto [lo, hi] = std::minmax_element(plant.u[i].begin(), plant.u[i].end());
    const double slack = std::max(std::abs(*lo), std::abs(*hi)) * 0x1p-23;
    EXPECT_GE(*lo, limits[i].min - slack) << plant.input_names[i] << " went below min";
    EXPECT_LE(*hi, limits[i].max + slack) << plant.input_names[i] << " went above max";
  }
}

}  // namespace excite::test
