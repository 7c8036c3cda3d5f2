// SPDX-License-Identifier: MIT
#pragma once
// A historian export (CSV) read for the tags asked for (issue 13 §1).
//
// Layout: optional `#` comment lines, a header row of column names, one row per timestamp.
// Fields are separated by commas; a field may be quoted ("…", "" for a quote inside). One
// column holds the timestamp (timestamp.hpp); each tag has its own column of absolute
// engineering values. A value is BAD when it is empty, not a number in full (`Bad`, `#N/A`,
// `I/O Timeout`, …), or NaN/inf; and when the tag has a quality column that says so: a
// column named `<tag>.quality`, `<tag>_quality` or `<tag>:quality` (any case), good when its
// text is `good` (any case) or an OPC quality code with the top two bits set (192–255).
//
// Errors (std::invalid_argument) name the file, the line, the column and what was expected:
// a tag that is not a column, an unparseable timestamp, timestamps not strictly increasing,
// a row with another number of fields than the header, no data rows.

#include <string>
#include <vector>

namespace excite::host::historian {

struct HistorianData {
  std::string file;
  std::vector<double> time_s;  // per data row, seconds (epoch or as written), increasing
  // Per requested tag (in the order asked): the value per data row, NaN when bad.
  std::vector<std::vector<double>> values;
  std::vector<std::size_t> bad_cells;  // per tag: bad values (incl. bad quality)
  std::vector<bool> has_quality;       // per tag: a quality column was found
};

/// Reads `path`; the timestamp is the column named `time_column`, or the first column
/// when it is empty.
HistorianData read_historian(const std::string& path, const std::string& time_column,
                             const std::vector<std::string>& tags);

/// The same from text in memory; `file` labels errors.
HistorianData parse_historian(const std::string& text, const std::string& file,
                              const std::string& time_column, const std::vector<std::string>& tags);

}  // namespace excite::host::historian
