// SPDX-License-Identifier: MIT
#pragma once
// A run log that is always whole (issue 19): each piece (the header, one row) goes to the
// file descriptor in write(2) calls of its own, never through a stdio buffer. A failed or
// short write (ENOSPC: the disk is full; EFBIG: a file-size limit, with SIGXFSZ ignored; EIO)
// cuts the file back to the end of the last whole piece (ftruncate) and is kept: every later
// append is refused, so the file reads back whole up to its last full row, and error() says
// why. No allocation, no exceptions: the gateway's log thread and excite-plant share it.

#include <cstddef>
#include <cstdint>
#include <span>

namespace excite::runlog {

class RowFile {
 public:
  /// `fd` stays the caller's (open before, closed after); appends start at `offset`, the
  /// bytes already in the file (0 for a file just created or truncated).
  explicit RowFile(int fd, std::uint64_t offset = 0) noexcept : fd_(fd), whole_(offset) {}

  /// Writes all of `bytes` (retrying interrupted and partial writes). False when a write
  /// failed now or earlier: the file is cut back to its last whole piece and error() is
  /// the errno of the first failure (EFBIG, ENOSPC, EIO, …).
  bool append(std::span<const char> bytes) noexcept;

  [[nodiscard]] bool failed() const noexcept { return error_ != 0; }
  [[nodiscard]] int error() const noexcept { return error_; }
  /// Bytes of whole pieces in the file.
  [[nodiscard]] std::uint64_t whole_bytes() const noexcept { return whole_; }

 private:
  int fd_;
  std::uint64_t whole_;
  int error_ = 0;
};

/// "No space left on device (ENOSPC)": the errno's text and its name, for messages,
/// formatted into `buffer` (returned).
const char* describe_errno(int error, char* buffer, std::size_t size) noexcept;

}  // namespace excite::runlog
