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

/// A number as the folder's files write it: a finite v as itself, NaN and ±inf as null.
nlohmann::json json_number(double v);
/// A number as they read it back: null (or anything not a number) as NaN.
double number_of(const nlohmann::json& v);

nlohmann::json config_json(const Config& config);
/// Throws std::runtime_error "FILE: FIELD = VALUE, expected …" for a malformed file.
Config read_config(const std::filesystem::path& file);

nlohmann::json unit_json(const UnitResult& unit);
/// Throws std::runtime_error "FILE: FIELD …, expected …" for a malformed file.
UnitResult read_unit(const std::filesystem::path& file);

/// Checks what read_unit() read against the run it belongs to, so a unit file holds only what
/// a run could have written: the unit's design, seed and Table 6.1 number, 1 … 10⁸ samples,
/// a sample time > 0, G(0) and its singular values of the plant's size (`outputs` ×
/// `inputs`) or none, the true G(0) when the plant is perturbed, the v_n angle in 0 … 90°,
/// the length grid of the run with prefixes within the run. Throws std::runtime_error
/// "FILE: FIELD = VALUE, expected …".
void check_unit(const UnitResult& unit_result, const Config& config, const Unit& unit, int outputs,
                int inputs, const std::filesystem::path& file);

/// DIR/units/DESIGN/seed-S.json for a unit.
std::filesystem::path unit_path(const std::filesystem::path& dir, const Config& config,
                                const Unit& unit);

/// The first field in which two configurations differ, the shard left out (empty: none):
/// "seeds = 10, expected 20".
std::string first_difference(const Config& found, const Config& expected);

}  // namespace excite::host::montecarlo
