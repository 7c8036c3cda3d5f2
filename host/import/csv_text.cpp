// SPDX-License-Identifier: MIT
#include "host/import/csv_text.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <stdexcept>

namespace excite::host::historian {

bool LineReader::next(std::string& line) {
  line.clear();
  if (!in_.good()) return false;
  std::streambuf* buf = in_.rdbuf();
  bool any = false;
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in_.setstate(std::ios::eofbit);
      break;
    }
    any = true;
    if (c == '\n') break;
    if (line.size() >= max_) {
      throw std::invalid_argument(file_ + ":" + std::to_string(line_no_ + 1) +
                                  ": line longer than " + std::to_string(max_) +
                                  " bytes, expected a text CSV line (is this a historian export?)");
    }
    line.push_back(static_cast<char>(c));
  }
  if (!any) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  ++line_no_;
  return true;
}

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return std::string(s);
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::vector<std::string> split(std::string_view line, char delimiter) {
  std::vector<std::string> out;
  std::string field;
  bool quoted_now = false;
  bool was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted_now) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted_now = false;
      } else {
        field += c;
      }
    } else if (c == '"' && trim(field).empty()) {
      quoted_now = true;
      was_quoted = true;
      field.clear();
    } else if (c == delimiter) {
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

std::string short_text(std::string_view cell) {
  // Invisible characters made visible (a byte-order mark, a no-break or zero-width space as
  // <U+XXXX>, a control byte as \xNN), so "Time" and "<U+FEFF>Time" do not look alike.
  constexpr std::size_t kShown = 40;
  std::string out;
  std::size_t i = 0;
  for (; i < cell.size() && i < kShown; ++i) {
    const auto byte = static_cast<unsigned char>(cell[i]);
    const auto next = [&](std::size_t k) {
      return i + k < cell.size() ? static_cast<unsigned char>(cell[i + k]) : 0;
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
    } else if (byte < 0x20 || byte == 0x7F) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += static_cast<char>(byte);
    }
  }
  if (i < cell.size()) out += "…";
  return out;
}

std::string quote_cell(std::string_view cell) {
  return "'" + short_text(cell) + "'";
}

std::string column_list(const std::vector<std::string>& header, std::size_t shown) {
  std::string out;
  for (std::size_t i = 0; i < header.size() && i < shown; ++i) {
    out += (i == 0 ? "" : ", ") + quote_cell(header[i]);
  }
  if (header.size() > shown) out += ", …";
  return out + " (" + std::to_string(header.size()) + " columns)";
}

}  // namespace excite::host::historian
