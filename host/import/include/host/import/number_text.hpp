// SPDX-License-Identifier: MIT
#pragma once
// A historian cell → a number, in the export's locale (issue 22):
//   - decimal point (default): `-1234.5`, `1e3`, `+2`, and thousands grouped by commas in
//     threes: `1,001.5`, `12,345,678`;
//   - decimal comma (`--decimal-comma`, a European export): `-1234,5`, `1.001,5`, `1,5e3`.
// A grouping separator must separate groups of exactly three digits after a first group
// of one to three (`1,5` is not a number with a decimal point, `1.5` not with a comma):
// anything else, NaN and inf are not numbers (nullopt), and import counts them as bad.

#include <optional>
#include <string_view>

namespace excite::host::historian {

std::optional<double> parse_number(std::string_view text, bool decimal_comma);

}  // namespace excite::host::historian
