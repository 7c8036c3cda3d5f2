// SPDX-License-Identifier: MIT
#include "base/config/document.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

namespace excite::config {

toml::table parse(std::string_view text, std::string_view source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const Position at{static_cast<std::uint32_t>(e.source().begin.line),
                      static_cast<std::uint32_t>(e.source().begin.column)};
    throw Error::text(source, at, e.description());
  }
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error::text(path.string(), {},
                      std::string("cannot be read (") + std::strerror(errno) + ")");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string describe(const toml::node& node) {
  std::ostringstream out;
  if (node.is_string()) {
    out << '"' << node.value<std::string>().value_or("") << '"';
  } else if (node.is_table()) {
    out << "(a table)";
  } else if (node.is_array()) {
    out << "(an array)";
  } else {
    node.visit([&out](const auto& v) { out << v; });
  }
  return out.str();
}

std::string format_number(double x) {
  std::array<char, 32> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  if (ec != std::errc{}) return "?";
  return std::string(buf.data(), end);
}

Position position_of(const toml::node& node) {
  const toml::source_region& region = node.source();
  if (!region.begin) return {};
  return {static_cast<std::uint32_t>(region.begin.line),
          static_cast<std::uint32_t>(region.begin.column)};
}

}  // namespace excite::config
