// SPDX-License-Identifier: MIT
#pragma once
// The summary of a Monte Carlo run over seeds, per design: median and 10–90 % range of every
// figure, the share of seeds meeting the accuracy criterion (accuracy.hpp) with its Wilson
// 95 % interval, the share at every length of the test-length grid, and T90:
//   T90 = the shortest grid length L such that the share of seeds meeting the criterion on
//   the first L of the run is ≥ 90 % at L and at every longer grid length (a share that
//   rises above 90 % and falls back below does not count); none when the whole run's share
//   is below 90 %.
// A function of the configuration and the units only (no time, no thread count, no shard),
// so the same units give the same bytes.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace excite::host::montecarlo {

inline constexpr double kT90Share = 0.90;

/// Index into `shares` (ascending lengths) of T90 as defined above; empty when none.
std::optional<std::size_t> t90_index(const std::vector<double>& shares);

/// summary.json's object. `units` are every unit of the run in all_units order.
nlohmann::json summary_json(const Config& config, const std::vector<UnitResult>& units);

/// The plain-text table of the same (for stdout).
std::string summary_text(const nlohmann::json& summary);

}  // namespace excite::host::montecarlo
