// SPDX-License-Identifier: MIT
#include "base/config/table.hpp"

#include <algorithm>
#include <cmath>

#include "base/config/document.hpp"

namespace excite::config {
namespace {

template <typename Keys>
void check_keys(const Table& t, const Keys& known) {
  for (const auto& [key, node] : t.raw()) {
    const std::string_view k = key.str();
    if (std::find(known.begin(), known.end(), k) != known.end()) continue;
    std::string list;
    for (const auto& name : known) {
      if (!list.empty()) list += ", ";
      list += name;
    }
    t.fail(k, describe(node) + " (unknown key)", "one of the known keys: " + list);
  }
}

std::string with_unit(std::string_view bound, std::string_view unit) {
  std::string out(bound);
  if (!unit.empty()) out.append(" ").append(unit);
  return out;
}

}  // namespace

std::string integer_range(std::int64_t lo, std::int64_t hi) {
  return "an integer " + std::to_string(lo) + ".." + std::to_string(hi);
}

Table::Table(const toml::table& table, std::string prefix, std::string_view source)
    : table_(table), prefix_(std::move(prefix)), source_(source) {}

std::string Table::field(std::string_view key) const {
  if (prefix_.empty()) return std::string(key);
  std::string out = prefix_;
  if (!key.empty() && key.front() != '[') out += '.';
  return out.append(key);
}

const toml::node* Table::get(std::string_view key) const {
  return table_.get(key);
}

// A missing key is reported at its table's header; the root has none worth naming (1:1).
Position Table::here() const {
  return prefix_.empty() ? Position{} : position_of(table_);
}

void Table::fail(std::string_view key, std::string value, std::string expected) const {
  // "key[i]" names an element of the array at "key": report it at the array.
  const toml::node* node = get(key.substr(0, key.find('[')));
  const Position at = node != nullptr ? position_of(*node) : here();
  throw Error(source_, at, field(key), std::move(value), std::move(expected));
}

void Table::fail_missing(std::string_view key, std::string expected) const {
  throw Error(source_, here(), field(key), "(missing)", std::move(expected));
}

void Table::only_keys(std::initializer_list<std::string_view> known) const {
  check_keys(*this, known);
}

void Table::only_keys(const std::vector<std::string>& known) const {
  check_keys(*this, known);
}

std::optional<std::string> Table::text(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_string()) fail(key, describe(*node), "a string");
  return *node->value<std::string>();
}

std::string Table::required_text(std::string_view key, std::string expected) const {
  if (auto s = text(key)) return *s;
  fail_missing(key, std::move(expected));
}

std::optional<std::string> Table::choice(std::string_view key,
                                         std::initializer_list<std::string_view> choices) const {
  auto s = text(key);
  if (!s || std::find(choices.begin(), choices.end(), *s) != choices.end()) return s;
  std::string list;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) list += i + 1 == choices.size() ? " or " : ", ";
    list.append("\"").append(choices.begin()[i]).append("\"");
  }
  fail(key, "\"" + *s + "\"", list);
}

std::optional<bool> Table::flag(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_boolean()) fail(key, describe(*node), "true or false");
  return *node->value<bool>();
}

std::optional<double> Table::number(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_number()) fail(key, describe(*node), "a number");
  const double x = *node->value<double>();
  if (!std::isfinite(x)) fail(key, describe(*node), "a finite number");
  return x;
}

double Table::required_number(std::string_view key) const {
  if (auto x = number(key)) return *x;
  fail_missing(key, "a number");
}

std::optional<double> Table::positive(std::string_view key, std::string_view unit) const {
  auto x = number(key);
  if (x && !(*x > 0.0)) fail(key, describe(*get(key)), with_unit("> 0", unit));
  return x;
}

std::optional<double> Table::non_negative(std::string_view key, std::string_view unit) const {
  auto x = number(key);
  if (x && !(*x >= 0.0)) fail(key, describe(*get(key)), with_unit(">= 0", unit));
  return x;
}

std::optional<std::int64_t> Table::integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                           std::string expected) const {
  const toml::node* node = get(key);
  if (node == nullptr) return std::nullopt;
  if (expected.empty()) expected = integer_range(lo, hi);
  // toml++ holds every integer as int64_t (it refuses wider literals at parse time), so the
  // comparison below cannot overflow.
  const auto v = node->value_exact<std::int64_t>();
  if (!v || *v < lo || *v > hi) fail(key, describe(*node), std::move(expected));
  return *v;
}

std::int64_t Table::required_integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                     std::string expected) const {
  if (auto v = integer(key, lo, hi, expected)) return *v;
  fail_missing(key, expected.empty() ? integer_range(lo, hi) : std::move(expected));
}

std::vector<double> Table::numbers(std::string_view key, bool scalar_allowed) const {
  const toml::node* node = get(key);
  if (node == nullptr) return {};
  if (scalar_allowed && node->is_number()) return {*number(key)};
  const toml::array* array = node->as_array();
  if (array == nullptr) {
    fail(key, describe(*node),
         scalar_allowed ? "a number or an array of numbers" : "an array of numbers");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = (*array)[i];
    const std::string item_field = field(key) + "[" + std::to_string(i) + "]";
    if (!item.is_number()) {
      throw Error(source_, position_of(item), item_field, describe(item), "a number");
    }
    const double x = *item.value<double>();
    if (!std::isfinite(x)) {
      throw Error(source_, position_of(item), item_field, describe(item), "a finite number");
    }
    out.push_back(x);
  }
  return out;
}

std::vector<std::string> Table::texts(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  if (array == nullptr) fail(key, describe(*node), "an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = (*array)[i];
    if (!item.is_string()) {
      throw Error(source_, position_of(item), field(key) + "[" + std::to_string(i) + "]",
                  describe(item), "a string");
    }
    out.push_back(*item.value<std::string>());
  }
  return out;
}

std::optional<Table> Table::table(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return std::nullopt;
  const toml::table* t = node->as_table();
  if (t == nullptr) fail(key, describe(*node), "a table [" + field(key) + "]");
  return Table(*t, field(key), source_);
}

Table Table::required_table(std::string_view key, std::string expected) const {
  if (auto t = table(key)) return *t;
  fail_missing(key, std::move(expected));
}

std::vector<Table> Table::tables(std::string_view key) const {
  const toml::node* node = get(key);
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  if (array == nullptr) fail(key, describe(*node), "an array of tables [[" + field(key) + "]]");
  std::vector<Table> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& item = (*array)[i];
    const std::string item_field = field(key) + "[" + std::to_string(i) + "]";
    const toml::table* t = item.as_table();
    if (t == nullptr)
      throw Error(source_, position_of(item), item_field, describe(item), "a table");
    out.emplace_back(*t, item_field, source_);
  }
  return out;
}

}  // namespace excite::config
