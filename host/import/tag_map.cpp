// SPDX-License-Identifier: MIT
#include "host/import/tag_map.hpp"

#include <toml++/toml.h>

#include <string>

#include "base/config/document.hpp"
#include "base/config/error.hpp"

namespace excite::host::historian {
namespace {

// A tag map error in the project's one configuration message form (base/config/error.hpp):
// "SOURCE:LINE:COL: FIELD = VALUE, expected WHAT".
[[noreturn]] void fail(std::string_view source, const toml::node& where, std::string field,
                       std::string expected, std::string_view note = {}) {
  const auto begin = where.source().begin;
  throw config::Error(source, {begin.line, begin.column}, std::move(field),
                      config::describe(where) + std::string(note), std::move(expected));
}

std::vector<TagSpec> read_role(const toml::table& root, const char* role, std::string_view source) {
  std::vector<TagSpec> out;
  const toml::node* node = root.get(role);
  if (node == nullptr) return out;
  const toml::array* entries = node->as_array();
  if (entries == nullptr) {
    fail(source, *node, role, std::string("an array of tables ([[") + role + "]])");
  }
  for (std::size_t e = 0; e < entries->size(); ++e) {
    const toml::table* t = (*entries)[e].as_table();
    const std::string at = std::string(role) + "[" + std::to_string(e + 1) + "]";
    if (t == nullptr) fail(source, (*entries)[e], at, "a table with tag, name, unit");
    TagSpec spec;
    for (const auto& [key, value] : *t) {
      const std::string k(key.str());
      if (k != "tag" && k != "name" && k != "unit") {
        fail(source, value, at + "." + k, "one of the known keys: tag, name, unit",
             " (unknown key)");
      }
      const auto* s = value.as_string();
      if (s == nullptr) fail(source, value, at + "." + k, "a string");
      (k == "tag" ? spec.tag : (k == "name" ? spec.name : spec.unit)) = s->get();
    }
    if (spec.tag.empty()) {
      const auto begin = t->source().begin;
      throw config::Error(source, {begin.line, begin.column}, at + ".tag", "(missing)",
                          "the historian column");
    }
    if (spec.name.empty()) spec.name = spec.tag;
    out.push_back(spec);
  }
  return out;
}

}  // namespace

TagMap parse_tag_map(std::string_view toml_text, std::string_view source_name) {
  const toml::table root = config::parse(toml_text, source_name);
  for (const auto& [key, value] : root) {
    if (key.str() != "mv" && key.str() != "cv") {
      fail(source_name, value, std::string(key.str()), "one of the known keys: [[mv]], [[cv]]",
           " (unknown key)");
    }
  }
  return TagMap{read_role(root, "mv", source_name), read_role(root, "cv", source_name)};
}

TagMap read_tag_map(const std::string& path) {
  return parse_tag_map(config::read_file(path), path);
}

}  // namespace excite::host::historian
