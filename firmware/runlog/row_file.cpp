// SPDX-License-Identifier: MIT
#include "firmware/runlog/row_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace excite::runlog {

bool RowFile::append(std::span<const char> bytes) noexcept {
  if (error_ != 0) return false;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    error_ = n < 0 ? errno : ENOSPC;  // write(2) returning 0 for a regular file: no room
    break;
  }
  if (error_ == 0) {
    whole_ += done;
    return true;
  }
  // Cut the piece written in part away: the file ends on its last whole piece. Truncating
  // frees blocks, so it works on a full disk; past a size limit it shrinks the file.
  if (done > 0) {
    [[maybe_unused]] const int t = ::ftruncate(fd_, static_cast<off_t>(whole_));
    [[maybe_unused]] const off_t o = ::lseek(fd_, static_cast<off_t>(whole_), SEEK_SET);
  }
  return false;
}

const char* describe_errno(int error, char* buffer, std::size_t size) noexcept {
  const char* name = nullptr;
  switch (error) {
    case ENOSPC:
      name = "ENOSPC";
      break;
    case EFBIG:
      name = "EFBIG";
      break;
    case EIO:
      name = "EIO";
      break;
    case EDQUOT:
      name = "EDQUOT";
      break;
    case EBADF:
      name = "EBADF";
      break;
    case EPIPE:
      name = "EPIPE";
      break;
    default:
      break;
  }
  char text[128];
  const char* what = strerror_r(error, text, sizeof text);  // GNU: returns the text
  if (name != nullptr) {
    std::snprintf(buffer, size, "%s (%s)", what, name);
  } else {
    std::snprintf(buffer, size, "%s (errno %d)", what, error);
  }
  return buffer;
}

}  // namespace excite::runlog
