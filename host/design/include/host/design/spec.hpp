// SPDX-License-Identifier: MIT
#pragma once
// The design spec: prior knowledge and the design to make, in TOML (host/README.md gives
// the format with a complete example).

#include <filesystem>
#include <string>
#include <string_view>

#include <optional>

#include "host/design/presets.hpp"
#include "host/design/prior_knowledge.hpp"

namespace excite::host {

struct DesignSpec {
  std::string design;  // preset acronym, or "multisine" for a plain multisine
  PriorKnowledge prior;
  std::optional<PlainMultisine> multisine;  // set when design == "multisine"
};

/// Parses a spec. Throws std::invalid_argument (config::Error, base/config) in the one
/// form "SOURCE:LINE:COL: FIELD = VALUE, expected …"; its message starts with `source_name`
/// and, where the TOML parser knows it, line:column, then names the key, the value and
/// what was expected: unknown keys, missing fields, wrong types, invalid prior knowledge
/// (validate()), a gain of the wrong size or a singular one.
DesignSpec parse_design_spec(std::string_view toml_text, std::string_view source_name);

/// Reads and parses a spec file.
DesignSpec load_design_spec(const std::filesystem::path& path);

}  // namespace excite::host
