// SPDX-License-Identifier: MIT
#pragma once
// Writing configuration files: the two TOML value forms every writer of the project uses
// (the plant server's configuration, the gateway's from `excite loop-config`, the
// register-map schema's entries), so what is written reads back as written through this
// room's reader.

#include <string>

namespace excite::config {

/// A number as TOML text that reads back exactly: the fewest significant digits (up to 17),
/// always with a '.' or an exponent (so TOML reads a float); a whole number below 2^53 as
/// "120.0", never "1.2e+02".
std::string toml_number(double x);

/// A TOML basic string with its quotes: '"', '\' and every control character escaped.
std::string toml_string(const std::string& text);

}  // namespace excite::config
