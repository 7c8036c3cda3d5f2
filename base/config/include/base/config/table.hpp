// SPDX-License-Identifier: MIT
#pragma once
// One TOML table read strictly: every getter names the dotted field, the value found and
// what was expected, in the one form of error.hpp, at the position of the offending node
// (of the table for a missing key). Getters of optional keys return std::nullopt (or an
// empty vector) when the key is absent; `required_*` refuse an absent key.
//
// A Table refers to the toml::table and the source name it was made from: both must
// outlive it.

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/config/error.hpp"

namespace excite::config {

class Table {
 public:
  /// `prefix` is the table's dotted path ("" for the root, "registers", "values[2]").
  Table(const toml::table& table, std::string prefix, std::string_view source);

  const toml::table& raw() const noexcept { return table_; }
  std::string_view source() const noexcept { return source_; }
  const std::string& prefix() const noexcept { return prefix_; }

  /// The dotted field name of `key` in this table.
  std::string field(std::string_view key) const;
  /// The node at `key`, or nullptr.
  const toml::node* get(std::string_view key) const;
  bool has(std::string_view key) const { return get(key) != nullptr; }

  /// Throws config::Error for `key` (at its node, else at the table).
  [[noreturn]] void fail(std::string_view key, std::string value, std::string expected) const;
  /// Throws "FIELD = (missing), expected …" for `key`.
  [[noreturn]] void fail_missing(std::string_view key, std::string expected) const;

  /// Strict keys: a key not in `known` is an error naming it and listing the known keys.
  void only_keys(std::initializer_list<std::string_view> known) const;
  void only_keys(const std::vector<std::string>& known) const;

  /// A string (no other type is converted).
  std::optional<std::string> text(std::string_view key) const;
  std::string required_text(std::string_view key, std::string expected = "a string") const;
  /// One of `choices` (the message lists them).
  std::optional<std::string> choice(std::string_view key,
                                    std::initializer_list<std::string_view> choices) const;

  /// true or false.
  std::optional<bool> flag(std::string_view key) const;

  /// A finite number (a TOML integer or float; inf and nan are refused).
  std::optional<double> number(std::string_view key) const;
  double required_number(std::string_view key) const;
  /// A finite number > 0 (`unit` is named in the message, e.g. "minutes").
  std::optional<double> positive(std::string_view key, std::string_view unit = {}) const;
  /// A finite number >= 0.
  std::optional<double> non_negative(std::string_view key, std::string_view unit = {}) const;

  /// A TOML integer in [lo, hi] (a float such as 3.0 is refused: integers are exact).
  /// `expected` replaces the default "an integer LO..HI" in the message.
  std::optional<std::int64_t> integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                      std::string expected = {}) const;
  std::int64_t required_integer(std::string_view key, std::int64_t lo, std::int64_t hi,
                                std::string expected = {}) const;

  /// An array of finite numbers; with `scalar_allowed` a single number is one element.
  std::vector<double> numbers(std::string_view key, bool scalar_allowed = false) const;
  /// An array of strings.
  std::vector<std::string> texts(std::string_view key) const;

  /// The sub-table at `key`, or nullopt when absent; an error if it is not a table.
  std::optional<Table> table(std::string_view key) const;
  Table required_table(std::string_view key, std::string expected = "a table") const;
  /// The array of tables at `key` ([[key]]), each named "prefix.key[i]"; empty if absent.
  std::vector<Table> tables(std::string_view key) const;

 private:
  Position here() const;

  const toml::table& table_;
  std::string prefix_;
  std::string_view source_;
};

/// "an integer LO..HI", the default expectation of Table::integer.
std::string integer_range(std::int64_t lo, std::int64_t hi);

}  // namespace excite::config
