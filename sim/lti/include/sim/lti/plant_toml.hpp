// SPDX-License-Identifier: MIT
#pragma once
// Plant files: a transfer-function matrix in TOML with the element grammar of
// parse_element.hpp (format in sim/lti/README.md). Unknown keys are errors.

#include <filesystem>
#include <string>
#include <string_view>

#include "sim/lti/transfer_matrix.hpp"

namespace excite::sim {

struct PlantDefinition {
  std::string name;         // "" when the file has none
  std::string description;  // free text, "" when absent
  TransferMatrix g;
};

/// Parses a plant from TOML text; `source` names it in error messages (a path or a plant
/// name). Throws std::invalid_argument (a config::Error) in the one form of
/// base/config: "SOURCE:LINE:COL: FIELD = VALUE, expected …"; an element the grammar
/// refuses reads "SOURCE:LINE:COL: <the grammar's message>" at the line of G.
PlantDefinition plant_from_toml(std::string_view toml_text, std::string_view source = "plant");

/// Reads and parses a plant file. Throws std::invalid_argument (also when unreadable).
PlantDefinition load_plant_file(const std::filesystem::path& path);

}  // namespace excite::sim
