// SPDX-License-Identifier: MIT
#pragma once
// A record written as it happens (the adaptive test's decisions.jsonl, issue 38 §1): every
// append reaches the kernel before it returns (no user-space buffer), so a reader of the
// file, or the operator after a crash, sees every whole append so far and at most the last
// one cut short. The file is created new, never replaced: an existing name, or a symbolic
// link even to nothing, is refused (O_EXCL | O_NOFOLLOW), so no link is followed and no
// earlier record is overwritten. The companion of whole_file.hpp, for the one file that is
// read while it is still being written.
// Errors are std::runtime_error "PATH: cannot be written (REASON)", as whole_file.hpp's.

#include <filesystem>
#include <string_view>

namespace excite::host {

class AppendFile {
 public:
  /// Creates `path` (0666 & ~umask); throws if it exists, is a link, or cannot be created.
  explicit AppendFile(const std::filesystem::path& path);
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;
  /// Closes the file; what was appended stays.
  ~AppendFile();

  /// Writes all of `bytes` at the end of the file (retrying short writes and EINTR);
  /// throws on an error (a full disk, `ulimit -f`).
  void append(std::string_view bytes);

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace excite::host
