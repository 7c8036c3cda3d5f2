// SPDX-License-Identifier: MIT
#pragma once
// A historian export (CSV) read for the tags asked for (issue 13 §1, issue 22), streamed a
// line at a time (never held whole), in one of three layouts:
//   - wide (default): optional `#` comment lines, a header row of column names, one row per
//     timestamp; the time column is the first (or the one named) and each tag has a column;
//   - per-tag time columns: the time column's name repeats (`Time,A,Time,B`: each tag takes
//     the nearest time column to its left), or `time_column_per_tag` (columns in pairs
//     TIME,VALUE whatever their names); a tag's cells may be empty where it has no sample;
//   - long (`long_format`): columns TAG,TIME,VALUE[,QUALITY] by position, one sample a row.
// `header_rows` rows after the header (units, descriptions) are skipped; a row whose first
// cell is `units`, `unit`, `eu`, `eng units`, `engineering units` or `uom` (any case) gives
// each tag's unit.
//
// A value is BAD when its cell is not a number in the export's locale (number_text.hpp:
// empty, `Bad`, `#N/A`, NaN, …) — counted per tag with the first three quoted with their
// line — or when the tag's quality column says so: a column `<tag>.quality`, `_quality`,
// `:quality` or ` quality` (any case) holding `good` or an OPC quality code (good: 192–255),
// or `<tag>.confidence` (same suffixes) holding a 0–100 confidence, good at or above
// `good_confidence` (which must then be given; given, it reads quality columns as
// confidences too).
//
// Refusals (std::invalid_argument, `FILE:LINE: FIELD = VALUE, expected WHAT`): a tag that is
// not a column (up to 20 columns listed, with the count) or whose name is not unique
// (address it as `NAME#2`, the second column of that name), an unparseable timestamp,
// timestamps of a tag not strictly increasing, zoned and naive timestamps mixed, a local
// time skipped or repeated by a daylight-saving change, epoch numbers whose magnitude is
// not the unit given (or, with none given, not seconds), a value beyond ±max_value, a row
// with another number of fields than the header, more than max_samples samples of a tag, a
// line longer than max_line_bytes, a tag with no samples, a quality column that makes every
// value bad (a 0–100 confidence read as OPC codes).

#include <cstddef>
#include <istream>
#include <limits>
#include <string>
#include <vector>

namespace excite::host::historian {

enum class Epoch { automatic, s, ms, us };

struct CsvOptions {
  char delimiter = ',';
  bool decimal_comma = false;
  std::string time_column;  // "" : the first column
  std::string time_format;  // "" : ISO 8601 or epoch numbers (timestamp.hpp)
  std::string time_zone;    // "" : naive timestamps read as given (as UTC)
  Epoch epoch = Epoch::automatic;
  std::size_t header_rows = 0;
  bool long_format = false;
  bool time_column_per_tag = false;
  double good_confidence = std::numeric_limits<double>::quiet_NaN();  // NaN: not given
  std::string from, to;  // a time window (ISO 8601 or epoch seconds; "" : open)
  double max_value = std::numeric_limits<double>::infinity();         // |value| above: refused
  std::size_t max_samples = std::numeric_limits<std::size_t>::max();  // per tag
  std::size_t max_line_bytes = std::size_t{60} << 20;  // a header of millions of columns
};

struct BadCell {
  std::size_t line = 0;
  std::string text;
};

/// One tag's samples: increasing times (seconds since the epoch, or as written), values
/// (NaN when bad) and the export's line of each.
struct TagSeries {
  std::vector<double> time_s;
  std::vector<double> values;
  std::vector<std::size_t> line;
};

struct HistorianData {
  std::string file;
  std::vector<TagSeries> series;                   // per requested tag, in the order asked
  std::vector<std::size_t> bad_cells;              // per tag: bad values (incl. bad quality)
  std::vector<std::vector<BadCell>> bad_examples;  // per tag: the first three not numbers
  std::vector<bool> has_quality;                   // per tag: a quality column was found
  std::vector<std::string> units;                  // per tag: from a units row ("" : none)
  std::size_t units_line = 0;                      // the units row's line (0: none)
};

/// Reads the file at `path`.
HistorianData read_historian(const std::string& path, const std::vector<std::string>& tags,
                             const CsvOptions& options = {});

/// The same from a stream; `file` labels errors.
HistorianData read_historian(std::istream& in, const std::string& file,
                             const std::vector<std::string>& tags, const CsvOptions& options);

/// The same from text in memory (tests).
HistorianData parse_historian(const std::string& text, const std::string& file,
                              const std::vector<std::string>& tags, const CsvOptions& options = {});

}  // namespace excite::host::historian
