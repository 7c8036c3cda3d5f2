// SPDX-License-Identifier: MIT
#include "host/import/tag_map.hpp"

#include <toml++/toml.h>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace excite::host::historian {
namespace {

[[noreturn]] void fail(std::string_view source, const toml::node* where, const std::string& what) {
  std::ostringstream msg;
  msg << source;
  if (where != nullptr && where->source().begin) {
    msg << ":" << where->source().begin.line << ":" << where->source().begin.column;
  }
  msg << ": " << what;
  throw std::invalid_argument(msg.str());
}

std::vector<TagSpec> read_role(const toml::table& root, const char* role, std::string_view source) {
  std::vector<TagSpec> out;
  const toml::node* node = root.get(role);
  if (node == nullptr) return out;
  const toml::array* entries = node->as_array();
  if (entries == nullptr) {
    fail(source, node, std::string(role) + ": expected an array of tables ([[" + role + "]])");
  }
  for (std::size_t e = 0; e < entries->size(); ++e) {
    const toml::table* t = (*entries)[e].as_table();
    const std::string at = std::string(role) + "[" + std::to_string(e + 1) + "]";
    if (t == nullptr) fail(source, &(*entries)[e], at + ": expected a table with tag, name, unit");
    TagSpec spec;
    for (const auto& [key, value] : *t) {
      const std::string k(key.str());
      if (k != "tag" && k != "name" && k != "unit") {
        fail(source, &value, at + "." + k + ": unknown key; expected tag, name or unit");
      }
      const auto* s = value.as_string();
      if (s == nullptr) fail(source, &value, at + "." + k + ": expected a string");
      (k == "tag" ? spec.tag : (k == "name" ? spec.name : spec.unit)) = s->get();
    }
    if (spec.tag.empty()) fail(source, t, at + ".tag: missing; expected the historian column");
    if (spec.name.empty()) spec.name = spec.tag;
    out.push_back(spec);
  }
  return out;
}

}  // namespace

TagMap parse_tag_map(std::string_view toml_text, std::string_view source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column << ": "
        << e.description();
    throw std::invalid_argument(msg.str());
  }
  for (const auto& [key, value] : root) {
    if (key.str() != "mv" && key.str() != "cv") {
      fail(source_name, &value,
           std::string(key.str()) + ": unknown key; expected [[mv]] or [[cv]]");
    }
  }
  return TagMap{read_role(root, "mv", source_name), read_role(root, "cv", source_name)};
}

TagMap read_tag_map(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_tag_map(text.str(), path);
}

}  // namespace excite::host::historian
