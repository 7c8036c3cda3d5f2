// SPDX-License-Identifier: MIT
#pragma once
// The run log's file at start-up: opened (created or truncated) before the field bus, and
// removed again if start-up fails before the log's header is written, so a refused start
// leaves no empty log behind (README, start-up order: exit 4, 5 and 12 leave no file).
// keep() marks the point after which the file stays whatever happens (the header and the
// rows that follow are the run's record); close() closes it once and says whether the
// close succeeded; the destructor closes a file still open and removes one not kept.

#include <cstdio>
#include <string>

namespace excite::app {

class RunLogFile {
 public:
  /// Opens `path` for writing; is_open() says whether that succeeded.
  explicit RunLogFile(std::string path);
  ~RunLogFile();
  RunLogFile(const RunLogFile&) = delete;
  RunLogFile& operator=(const RunLogFile&) = delete;

  [[nodiscard]] bool is_open() const noexcept { return file_ != nullptr; }
  [[nodiscard]] std::FILE* get() const noexcept { return file_; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

  /// From here on the file is the run's record: never removed.
  void keep() noexcept { keep_ = true; }
  /// Closes the file (once); false when fclose failed (the last buffered bytes may be lost).
  bool close() noexcept;

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  bool opened_ = false;  // this object created (or truncated) the file
  bool keep_ = false;
};

}  // namespace excite::app
