// SPDX-License-Identifier: MIT
#pragma once
// The files of a Monte Carlo folder (host/montecarlo/README.md):
//   DIR/run.json                       the Config (work.hpp), shard included
//   DIR/units/DESIGN/seed-S.json       one finished unit (unit.hpp), written whole
// Numbers are written so that they read back bit for bit (NaN and ±inf as null → NaN), so a
// summary made from the files is the same whichever process wrote them.

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace excite::host::montecarlo {

nlohmann::json config_json(const Config& config);
/// Throws std::runtime_error "FILE: FIELD = VALUE, expected …" for a malformed file.
Config read_config(const std::filesystem::path& file);

nlohmann::json unit_json(const UnitResult& unit);
/// Throws std::runtime_error "FILE: FIELD …, expected …" for a malformed file.
UnitResult read_unit(const std::filesystem::path& file);

/// DIR/units/DESIGN/seed-S.json for a unit.
std::filesystem::path unit_path(const std::filesystem::path& dir, const Config& config,
                                const Unit& unit);

/// The first field in which two configurations differ, the shard left out (empty: none):
/// "seeds = 10, expected 20".
std::string first_difference(const Config& found, const Config& expected);

}  // namespace excite::host::montecarlo
