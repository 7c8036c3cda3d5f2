// SPDX-License-Identifier: MIT
#include "host/output/folder_marker.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <sstream>

#include "host/output/whole_file.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kHeader = "excite output v1 ";
constexpr off_t kMaxMarkerBytes = 16 << 20;

// The marker's text, read without following a link and only from a regular file.
std::optional<std::string> marker_text(const fs::path& dir) {
  const int fd =
      ::open((dir / kFolderMarker).c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  struct stat info {};
  std::optional<std::string> text;
  if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size <= kMaxMarkerBytes) {
    std::string bytes(static_cast<std::size_t>(info.st_size), '\0');
    std::size_t got = 0;
    while (got < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    if (got == bytes.size()) text = std::move(bytes);
  }
  ::close(fd);
  return text;
}

}  // namespace

std::vector<std::string> folder_entries(const fs::path& dir) {
  std::vector<std::string> entries;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path relative = it->path().lexically_relative(dir);
    if (relative == kFolderMarker) continue;
    const bool folder = it->is_directory(ec) && !it->is_symlink(ec);
    entries.push_back(relative.generic_string() + (folder ? "/" : ""));
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

void write_folder_marker(const fs::path& dir, std::string_view kind,
                         const std::vector<std::string>& entries) {
  std::string text = std::string(kHeader) + std::string(kind) + "\n";
  for (const std::string& e : entries) text += e + "\n";
  write_whole_file(dir / kFolderMarker, text);
}

std::optional<std::vector<std::string>> marked_entries(const fs::path& dir, std::string_view kind) {
  const std::optional<std::string> text = marker_text(dir);
  if (!text) return std::nullopt;
  std::istringstream in(*text);
  std::string line;
  if (!std::getline(in, line) || line != std::string(kHeader) + std::string(kind))
    return std::nullopt;
  std::vector<std::string> entries;
  while (std::getline(in, line)) entries.push_back(line);
  std::sort(entries.begin(), entries.end());
  return entries;
}

std::string foreign_entry(const fs::path& dir, std::string_view kind) {
  const std::optional<std::vector<std::string>> listed = marked_entries(dir, kind);
  if (!listed) return "no " + std::string(kFolderMarker) + " of an excite " + std::string(kind);
  for (const std::string& e : folder_entries(dir)) {
    if (!std::binary_search(listed->begin(), listed->end(), e))
      return e + " is not a file excite wrote";
  }
  return {};
}

}  // namespace excite::host
