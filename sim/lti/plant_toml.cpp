// SPDX-License-Identifier: MIT
#include "sim/lti/plant_toml.hpp"

#include <sstream>
#include <stdexcept>

#include "base/config/document.hpp"
#include "base/config/table.hpp"

namespace excite::sim {
namespace {

constexpr const char* kElementExample = "an element string such as \"4.09 e^-1.3s / (33s+1)\"";

// G: rows of element strings; a bare number is a static gain.
std::vector<std::vector<std::string>> element_texts(const config::Table& root) {
  const toml::node* g = root.get("G");
  if (g == nullptr) root.fail_missing("G", "an array of rows of element strings");
  const toml::array* rows = g->as_array();
  if (rows == nullptr || rows->empty()) {
    root.fail("G", config::describe(*g), "a non-empty array of rows of element strings");
  }
  std::vector<std::vector<std::string>> text;
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const std::string row_field = "G[" + std::to_string(i) + "]";
    const toml::array* row = (*rows)[i].as_array();
    if (row == nullptr) {
      throw config::Error(root.source(), config::position_of((*rows)[i]), row_field,
                          config::describe((*rows)[i]), "an array of element strings");
    }
    std::vector<std::string> r;
    for (std::size_t j = 0; j < row->size(); ++j) {
      const toml::node& cell = (*row)[j];
      if (const auto s = cell.value_exact<std::string>()) {
        r.push_back(*s);
      } else if (cell.is_number()) {
        std::ostringstream os;
        os.precision(17);
        os << *cell.value<double>();
        r.push_back(os.str());
      } else {
        throw config::Error(root.source(), config::position_of(cell),
                            row_field + "[" + std::to_string(j) + "]", config::describe(cell),
                            kElementExample);
      }
    }
    text.push_back(std::move(r));
  }
  return text;
}

}  // namespace

PlantDefinition plant_from_toml(std::string_view toml_text, std::string_view source) {
  const toml::table doc = config::parse(toml_text, source);
  const config::Table root(doc, "", source);
  root.only_keys({"name", "description", "time_unit", "inputs", "outputs", "allow_unstable", "G"});
  if (const auto unit = root.text("time_unit"); unit && *unit != "min") {
    root.fail("time_unit", "\"" + *unit + "\"", "\"min\" (all times are in minutes)");
  }
  ElementRules rules;
  rules.allow_unstable = root.flag("allow_unstable").value_or(false);
  const std::vector<std::vector<std::string>> text = element_texts(root);
  PlantDefinition def{root.text("name").value_or(""), root.text("description").value_or(""),
                      TransferMatrix(1, 1)};
  const std::vector<std::string> inputs = root.texts("inputs");
  const std::vector<std::string> outputs = root.texts("outputs");
  try {
    def.g = TransferMatrix::parse(text, inputs, outputs, rules);
  } catch (const std::invalid_argument& e) {
    // The grammar's message names the row, column, element text and position in it.
    throw config::Error::text(source, config::position_of(*doc.get("G")), e.what());
  }
  return def;
}

PlantDefinition load_plant_file(const std::filesystem::path& path) {
  return plant_from_toml(config::read_file(path), path.string());
}

}  // namespace excite::sim
