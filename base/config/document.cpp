// SPDX-License-Identifier: MIT
#include "base/config/document.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
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

const char* file_type_name(mode_t mode) {
  if (S_ISREG(mode)) return "regular file";
  if (S_ISDIR(mode)) return "folder";
  if (S_ISFIFO(mode)) return "FIFO";
  if (S_ISCHR(mode)) return "character device";
  if (S_ISBLK(mode)) return "block device";
  if (S_ISSOCK(mode)) return "socket";
  return "not a regular file";
}

namespace {

// Closes the descriptor on every path out of read_file.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) close(fd);
  }
};

}  // namespace

std::string read_file(const std::filesystem::path& path) {
  const Descriptor file{open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  struct stat st {};
  if (file.fd < 0 || fstat(file.fd, &st) != 0) {
    throw Error::text(path.string(), {},
                      std::string("cannot be read (") + std::strerror(errno) + ")");
  }
  if (!S_ISREG(st.st_mode)) {
    throw Error::text(path.string(), {},
                      std::string("file type = ") + file_type_name(st.st_mode) +
                          ", expected a regular file");
  }
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) {
    throw Error::text(path.string(), {},
                      "size = " + std::to_string(st.st_size) + " bytes, expected at most " +
                          std::to_string(kMaxFileBytes) + " bytes");
  }
  std::string text(static_cast<std::size_t>(st.st_size) + 1, '\0');  // one more: it grew
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = read(file.fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw Error::text(path.string(), {},
                        std::string("cannot be read (") + std::strerror(errno) + ")");
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > static_cast<std::size_t>(st.st_size)) {
    throw Error::text(path.string(), {},
                      "size = growing while read, expected a file written whole");
  }
  text.resize(got);
  return text;
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
