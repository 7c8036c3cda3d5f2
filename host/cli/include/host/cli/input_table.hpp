// SPDX-License-Identifier: MIT
#pragma once
// The thesis's input-signal table (plant-friendliness per channel), as text and as JSON.

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

#include "host/measures/input_measures.hpp"

namespace excite::host::cli {

/// `cf_continuous`: per channel, the crest factor of the continuous multisine (NaN for other
/// channels); the column is printed when any channel has one.
void print_input_measures(std::ostream& out, const InputMeasures& m,
                          const std::vector<std::string>& channel_names,
                          const std::vector<double>& cf_continuous);

/// {"channels":[{"name","cf","cf_continuous","pips","pf","phi","phi_smooth","rms","min","max",
/// "max_step"}…], "average":{same keys but name}}; cf_continuous is null for channels that
/// are not multisines.
nlohmann::json input_measures_json(const InputMeasures& m,
                                   const std::vector<std::string>& channel_names,
                                   const std::vector<double>& cf_continuous);

}  // namespace excite::host::cli
