// SPDX-License-Identifier: MIT
#pragma once
// The text layer of a historian export (issue 22): lines read in bounded memory and split
// into fields, and cells quoted in messages with a bounded length.
//
//   - LineReader reads one line at a time from a stream (never the whole file); a line longer
//     than its limit (a binary file, /dev/zero) is an error naming the file and line.
//   - split() separates fields by one delimiter character; a field may be quoted ("…", ""
//     for a quote inside), and unquoted fields lose surrounding blanks.
//   - quote_cell() renders a cell for a message: in quotes, at most 40 characters (then "…").

#include <cstddef>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace excite::host::historian {

class LineReader {
 public:
  LineReader(std::istream& in, std::string file, std::size_t max_line_bytes)
      : in_(in), file_(std::move(file)), max_(max_line_bytes) {}
  /// The next line without its end (\n, \r\n); false at the end of the stream. Throws
  /// std::invalid_argument when a line exceeds the limit.
  bool next(std::string& line);
  std::size_t line_number() const { return line_no_; }

 private:
  std::istream& in_;
  std::string file_;
  std::size_t max_;
  std::size_t line_no_ = 0;
};

std::vector<std::string> split(std::string_view line, char delimiter);
std::string trim(std::string_view s);
std::string lower(std::string_view s);
std::string quote_cell(std::string_view cell);
/// The same without the quotes (a column name in a message).
std::string short_text(std::string_view cell);

/// "a, b, c … (N columns)": at most `shown` names of a header, and the count.
std::string column_list(const std::vector<std::string>& header, std::size_t shown = 20);

}  // namespace excite::host::historian
