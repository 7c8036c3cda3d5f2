// SPDX-License-Identifier: MIT
#pragma once
// Writes an excite-plant configuration as TOML (the format parse_server_config reads, see
// sim/server/README.md): used by `excite loop-config` so the plant's and the gateway's
// register maps come from one description. parse_server_config(format_server_config(c))
// gives back c (numbers are written with the fewest digits that read back exactly).

#include <string>

#include "sim/server/server_config.hpp"

namespace excite::sim::server {

/// The configuration as TOML text, with a comment line `header` (may be empty) on top.
std::string format_server_config(const ServerConfig& config, const std::string& header = "");

/// A number as TOML text that reads back exactly: the fewest significant digits (up to 17),
/// always with a '.' or an exponent (so TOML reads a float).
std::string toml_number(double x);

/// A TOML basic string with quotes, '"' and '\' escaped.
std::string toml_string(const std::string& text);

}  // namespace excite::sim::server
