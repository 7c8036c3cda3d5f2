// SPDX-License-Identifier: MIT
#pragma once
// Reading a configuration text: the file's bytes, the TOML document, and how a node is
// named in messages (its value as written, its position).

#include <toml++/toml.h>

#include <filesystem>
#include <string>
#include <string_view>

#include "base/config/error.hpp"

namespace excite::config {

/// Parses TOML text; `source` names it in messages. A syntax error throws config::Error
/// "SOURCE:LINE:COL: <description>".
toml::table parse(std::string_view text, std::string_view source);

/// The whole file as text; throws config::Error "PATH: cannot be read (<reason>)".
std::string read_file(const std::filesystem::path& path);

/// A node's value as messages show it: strings quoted, numbers and booleans as written,
/// "(a table)" and "(an array)" for containers.
std::string describe(const toml::node& node);

/// A number as messages show it: the shortest text that reads back to the same double
/// ("0.1", "-2", "1e+300").
std::string format_number(double x);

/// Where a node starts in its text; line 0 when toml++ does not know (e.g. the root).
Position position_of(const toml::node& node);

}  // namespace excite::config
