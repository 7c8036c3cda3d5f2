// SPDX-License-Identifier: MIT
#pragma once
// The named reference plants of SPEC §7, defined once as TOML text in the element grammar
// (plants.cpp) and parsed by the same loader as user plant files. Time in minutes.
//
//   alatiqi4x4    4×4 column/side-stripper, Alatiqi & Luyben (thesis 6.3.1 = B.0.5)
//   column2x2     2×2 distillation column, Skogestad et al. (5.3.1 = B.0.2)
//   heatex2x2     2×2 heat exchanger, Jacobsen & Skogestad (5.3.3 = B.0.1)
//   woodberry2x2  Wood–Berry column (B.0.3)
//   column3x3     3×3 distillation column (B.0.4)
//   twoweak4x4    4×4 example with two small singular values (6.4.1 = B.0.6)

#include <string>
#include <string_view>
#include <vector>

#include "sim/lti/plant_toml.hpp"
#include "sim/lti/transfer_matrix.hpp"

namespace excite::sim {

/// Names of the library plants, in the order above.
std::vector<std::string> library_plant_names();

/// The plant called `name`. Throws std::invalid_argument listing the known names.
TransferMatrix library_plant(std::string_view name);

/// The plant with its name and description (the citation).
PlantDefinition library_plant_definition(std::string_view name);

/// The TOML source of the plant (the one definition; write it to a file to start a variant).
std::string_view library_plant_toml(std::string_view name);

}  // namespace excite::sim
