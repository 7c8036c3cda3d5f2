// SPDX-License-Identifier: MIT
#pragma once
// The model file `excite identify -o MODEL` writes and `excite validate` reads: the
// identified model as JSON (host/README.md). It is also what --json prints.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "host/export/formats.hpp"
#include "host/identify/identify.hpp"

namespace excite::host::cli {

/// {"format":"excite model v1","sample_time_min","inputs":[names],"outputs":[{"name","fit",
///  "elements":[{"input","K","Tp1","Tp2","Td","se":{…},"status","reason"}…]}…],
///  "gain","singular_values","condition_number","xi","rga"}; null for what is unknown.
nlohmann::json model_json(const IdentificationResult& result,
                          const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names);

/// Reads a model file. Throws std::invalid_argument "<path>: <field>: <what was expected>".
IdentifiedModel read_model_file(const std::filesystem::path& path);

/// The same with the names of the inputs and outputs (`source` is the path).
NamedModel read_named_model_file(const std::filesystem::path& path);

}  // namespace excite::host::cli
