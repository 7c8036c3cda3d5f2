// SPDX-License-Identifier: MIT
#include "host/import/historian_csv.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "host/import/timestamp.hpp"

namespace excite::host::historian {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return std::string(s);
}

// Splits one CSV line; quoted fields may hold commas and "" for a quote.
std::vector<std::string> split(std::string_view line) {
  std::vector<std::string> out;
  std::string field;
  bool quoted = false;
  bool was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"' && trim(field).empty()) {
      quoted = true;
      was_quoted = true;
      field.clear();
    } else if (c == ',') {
      out.push_back(was_quoted ? field : trim(field));
      field.clear();
      was_quoted = false;
    } else {
      field += c;
    }
  }
  out.push_back(was_quoted ? field : trim(field));
  return out;
}

double value_of(const std::string& text) {
  double v = 0.0;
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto [end, ec] = std::from_chars(b, e, v);
  if (text.empty() || ec != std::errc() || end != e || !std::isfinite(v)) return kNaN;
  return v;
}

bool quality_good(const std::string& text) {
  if (lower(text) == "good") return true;
  unsigned q = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), q);
  return ec == std::errc() && end == text.data() + text.size() && q <= 255U && (q & 0xC0U) == 0xC0U;
}

std::string where(const std::string& file, std::size_t line, std::size_t column,
                  const std::string& name) {
  return file + ":" + std::to_string(line) + ": column " + std::to_string(column) + " (" + name +
         "): ";
}

// A column name as a message shows it: invisible characters made visible (a byte-order
// mark, a no-break or zero-width space as <U+XXXX>, a control byte as \xNN), so "Time" and
// "<U+FEFF>Time" do not look alike.
std::string visible(const std::string& name) {
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto byte = static_cast<unsigned char>(name[i]);
    const auto next = [&](std::size_t k) {
      return i + k < name.size() ? static_cast<unsigned char>(name[i + k]) : 0;
    };
    if (byte == 0xEF && next(1) == 0xBB && next(2) == 0xBF) {
      out += "<U+FEFF>";
      i += 2;
    } else if (byte == 0xE2 && next(1) == 0x80 && next(2) == 0x8B) {
      out += "<U+200B>";
      i += 2;
    } else if (byte == 0xC2 && next(1) == 0xA0) {
      out += "<U+00A0>";
      i += 1;
    } else if (byte < 0x20 || byte == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += name[i];
    }
  }
  return out;
}

}  // namespace

HistorianData parse_historian(const std::string& text, const std::string& file,
                              const std::string& time_column,
                              const std::vector<std::string>& tags) {
  // A UTF-8 byte-order mark (Excel's "CSV UTF-8") is encoding, not the first column's name.
  const bool bom = text.rfind("\xEF\xBB\xBF", 0) == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::string> header;
  std::size_t header_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    header = split(t);
    header_line = line_no;
    break;
  }
  if (header.empty()) {
    throw std::invalid_argument(file +
                                ": no header row; expected a row of column names "
                                "(timestamp, then one column per tag)");
  }
  const auto column_of = [&](const std::string& name) -> std::ptrdiff_t {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : it - header.begin();
  };
  std::string columns;
  for (const auto& h : header) columns += (columns.empty() ? "" : ", ") + visible(h);
  std::size_t time_col = 0;
  if (!time_column.empty()) {
    const std::ptrdiff_t c = column_of(time_column);
    if (c < 0) {
      throw std::invalid_argument(file + ":" + std::to_string(header_line) + ": time column '" +
                                  visible(time_column) +
                                  "' is not in the header; columns: " + columns);
    }
    time_col = static_cast<std::size_t>(c);
  }
  HistorianData d;
  d.file = file;
  std::vector<std::size_t> value_col;
  std::vector<std::ptrdiff_t> quality_col;
  for (const auto& tag : tags) {
    const std::ptrdiff_t c = column_of(tag);
    if (c < 0 || static_cast<std::size_t>(c) == time_col) {
      throw std::invalid_argument(file + ":" + std::to_string(header_line) + ": tag '" +
                                  visible(tag) +
                                  "' is not a value column of the header; columns: " + columns);
    }
    value_col.push_back(static_cast<std::size_t>(c));
    std::ptrdiff_t q = -1;
    for (std::size_t h = 0; h < header.size(); ++h) {
      const std::string name = lower(header[h]);
      const std::string base = lower(tag);
      if (name == base + ".quality" || name == base + "_quality" || name == base + ":quality") {
        q = static_cast<std::ptrdiff_t>(h);
      }
    }
    quality_col.push_back(q);
    d.has_quality.push_back(q >= 0);
  }
  d.values.assign(tags.size(), {});
  d.bad_cells.assign(tags.size(), 0);

  std::string previous_time_text;
  std::size_t previous_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty()) continue;
    const std::vector<std::string> f = split(t);
    if (f.size() != header.size()) {
      throw std::invalid_argument(file + ":" + std::to_string(line_no) + ": " +
                                  std::to_string(f.size()) + " fields; expected " +
                                  std::to_string(header.size()) + " as in the header (line " +
                                  std::to_string(header_line) + ")");
    }
    const std::string& ts = f[time_col];
    const std::optional<double> s = parse_timestamp(ts);
    if (!s) {
      throw std::invalid_argument(where(file, line_no, time_col + 1, header[time_col]) + "'" + ts +
                                  "' is not a timestamp; expected ISO 8601 "
                                  "(2026-11-24T06:50:00, optional Z or ±HH:MM) or epoch seconds");
    }
    if (!d.time_s.empty() && !(*s > d.time_s.back())) {
      throw std::invalid_argument(where(file, line_no, time_col + 1, header[time_col]) + "'" + ts +
                                  "' is not after '" + previous_time_text + "' (line " +
                                  std::to_string(previous_line) +
                                  "); expected strictly increasing timestamps");
    }
    d.time_s.push_back(*s);
    previous_time_text = ts;
    previous_line = line_no;
    for (std::size_t g = 0; g < tags.size(); ++g) {
      double v = value_of(f[value_col[g]]);
      if (quality_col[g] >= 0 && !quality_good(f[static_cast<std::size_t>(quality_col[g])])) {
        v = kNaN;
      }
      if (std::isnan(v)) ++d.bad_cells[g];
      d.values[g].push_back(v);
    }
  }
  if (d.time_s.empty()) {
    throw std::invalid_argument(file + ":" + std::to_string(header_line) +
                                ": no data rows after the header; expected one row per timestamp");
  }
  return d;
}

HistorianData read_historian(const std::string& path, const std::string& time_column,
                             const std::vector<std::string>& tags) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_historian(text.str(), path, time_column, tags);
}

}  // namespace excite::host::historian
