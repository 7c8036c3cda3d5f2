// SPDX-License-Identifier: MIT
#pragma once
// The thesis's input-signal table (plant-friendliness per channel), as text and as JSON.

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

#include "host/measures/input_measures.hpp"

namespace excite::host::cli {

void print_input_measures(std::ostream& out, const InputMeasures& m,
                          const std::vector<std::string>& channel_names);

/// {"channels":[{"cf","pips","pf","phi","phi_smooth","rms","min","max","max_step"}…],
///  "average":{same keys}}
nlohmann::json input_measures_json(const InputMeasures& m,
                                   const std::vector<std::string>& channel_names);

}  // namespace excite::host::cli
