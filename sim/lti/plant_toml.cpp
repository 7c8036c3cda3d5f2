// SPDX-License-Identifier: MIT
#include "sim/lti/plant_toml.hpp"

#include <toml++/toml.h>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace excite::sim {
namespace {

[[noreturn]] void fail(std::string_view source, const std::string& what) {
  throw std::invalid_argument(std::string(source) + ": " + what);
}

std::vector<std::string> string_array(const toml::table& t, std::string_view key,
                                      std::string_view source) {
  std::vector<std::string> out;
  const toml::node* node = t.get(key);
  if (node == nullptr) return out;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) fail(source, "key '" + std::string(key) + "': expected an array of strings");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const auto s = (*arr)[i].value<std::string>();
    if (!s) {
      fail(source,
           "key '" + std::string(key) + "' entry " + std::to_string(i + 1) + ": expected a string");
    }
    out.push_back(*s);
  }
  return out;
}

}  // namespace

PlantDefinition plant_from_toml(std::string_view toml_text, std::string_view source) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ": TOML syntax error at line " << e.source().begin.line << ", column "
       << e.source().begin.column << ": " << e.description();
    throw std::invalid_argument(os.str());
  }
  static const std::set<std::string> known = {"name",    "description",    "time_unit", "inputs",
                                              "outputs", "allow_unstable", "G"};
  for (const auto& [key, value] : root) {
    if (known.count(std::string(key.str())) == 0) {
      fail(source, "unknown key '" + std::string(key.str()) +
                       "', expected one of name, description, time_unit, inputs, outputs, "
                       "allow_unstable, G");
    }
  }
  if (const toml::node* unit = root.get("time_unit")) {
    const auto u = unit->value<std::string>();
    if (!u || *u != "min") {
      fail(source, "key 'time_unit': expected \"min\" (all times are in minutes)");
    }
  }
  ElementRules rules;
  if (const toml::node* au = root.get("allow_unstable")) {
    const auto b = au->value<bool>();
    if (!b) fail(source, "key 'allow_unstable': expected true or false");
    rules.allow_unstable = *b;
  }
  const toml::node* g_node = root.get("G");
  if (g_node == nullptr)
    fail(source, "missing key 'G': expected an array of rows of element strings");
  const toml::array* rows = g_node->as_array();
  if (rows == nullptr || rows->empty()) {
    fail(source, "key 'G': expected a non-empty array of rows of element strings");
  }
  std::vector<std::vector<std::string>> text;
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const toml::array* row = (*rows)[i].as_array();
    if (row == nullptr)
      fail(source, "G row " + std::to_string(i + 1) + ": expected an array of strings");
    std::vector<std::string> r;
    for (std::size_t j = 0; j < row->size(); ++j) {
      const toml::node& cell = (*row)[j];
      if (const auto s = cell.value_exact<std::string>()) {
        r.push_back(*s);
      } else if (const auto d = cell.value<double>()) {
        std::ostringstream os;
        os.precision(17);
        os << *d;
        r.push_back(os.str());  // a bare number is a static gain
      } else {
        fail(source, "G row " + std::to_string(i + 1) + ", column " + std::to_string(j + 1) +
                         ": expected an element string such as \"4.09 e^-1.3s / (33s+1)\"");
      }
    }
    text.push_back(std::move(r));
  }
  PlantDefinition def{root["name"].value_or(std::string{}),
                      root["description"].value_or(std::string{}), TransferMatrix(1, 1)};
  try {
    def.g = TransferMatrix::parse(text, string_array(root, "inputs", source),
                                  string_array(root, "outputs", source), rules);
  } catch (const std::invalid_argument& e) {
    fail(source, e.what());
  }
  return def;
}

PlantDefinition load_plant_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path.string() + ": cannot open plant file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return plant_from_toml(buffer.str(), path.string());
}

}  // namespace excite::sim
