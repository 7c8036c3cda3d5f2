// SPDX-License-Identifier: MIT
#pragma once
// Reading a configuration text: the file's bytes, the TOML document, and how a node is
// named in messages (its value as written, its position).

#include <sys/types.h>
#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "base/config/error.hpp"

namespace excite::config {

/// Parses TOML text; `source` names it in messages. A syntax error throws config::Error
/// "SOURCE:LINE:COL: <description>".
toml::table parse(std::string_view text, std::string_view source);

/// What `mode` (stat's st_mode) says a file is, as messages name it: "regular file", "folder",
/// "FIFO", "character device", "block device", "socket".
const char* file_type_name(mode_t mode);

/// The largest configuration text read (gateway and plant-server configurations, plant files,
/// design specs, tag maps, controller files: kilobytes in practice).
inline constexpr std::uintmax_t kMaxFileBytes = 16u << 20;

/// The whole file as text (issue 40 §5: every input read whole has a bound). What the name
/// names after its links must be a regular file of at most kMaxFileBytes; it is opened
/// without blocking and checked on the open descriptor, so a FIFO is refused, never waited
/// on, and /dev/zero or a file that grows while read is refused at the bound. Throws
/// config::Error "PATH: cannot be read (<reason>)", "PATH: file type = FIFO, expected a
/// regular file", "PATH: size = N bytes, expected at most 16777216 bytes".
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
