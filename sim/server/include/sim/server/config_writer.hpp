// SPDX-License-Identifier: MIT
#pragma once
// Writes an excite-plant configuration as TOML (the format parse_server_config reads, see
// sim/server/README.md): used by `excite loop-config` so the plant's and the gateway's
// register maps come from one description. parse_server_config(format_server_config(c))
// gives back c (numbers are written with the fewest digits that read back exactly). The
// register entries and the map's settings are written by the schema's own writer beside
// its reader (hal/modbus/register_entry_toml.hpp), as the gateway's side is.

#include <string>

#include "base/config/writer.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {

/// The configuration as TOML text, with a comment line `header` (may be empty) on top.
std::string format_server_config(const ServerConfig& config, const std::string& header = "");

// The configuration room's value forms (base/config/writer.hpp).
using config::toml_number;
using config::toml_string;

}  // namespace excite::sim::server
