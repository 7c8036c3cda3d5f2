// SPDX-License-Identifier: MIT
#include "firmware/app/inbox_files.hpp"

#include <fcntl.h>
#include <stdio.h>  // renameat2 (glibc ≥ 2.28, _GNU_SOURCE)
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace excite::app {

namespace {

std::string octal_mode(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

std::string check_inbox_folder(const std::string& dir) {
  struct stat st {};
  if (lstat(dir.c_str(), &st) != 0) {
    return "--segment-inbox = " + dir + " (" + std::strerror(errno) +
           "), expected an existing folder";
  }
  const uid_t me = geteuid();
  std::string why;
  if (!S_ISDIR(st.st_mode)) {
    why = kind_of(st.st_mode);
  } else if (st.st_uid != me) {
    why = "owned by uid " + std::to_string(st.st_uid);
  } else if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
    why = "mode " + octal_mode(st.st_mode) + ": writable by others";
  }
  if (why.empty()) return "";
  return "--segment-inbox = " + dir + " (" + why + "), expected a folder owned by this user (uid " +
         std::to_string(me) +
         ") and writable by nobody else (chmod go-w): whoever can write into it can drop a "
         "plan segment or plant a link";
}

SegmentFile read_segment_file(const std::string& path, std::size_t max_bytes) {
  SegmentFile f;
  struct stat named {};
  if (lstat(path.c_str(), &named) != 0) return f;  // nothing there
  f.present = true;
  const int fd = open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    f.refusal = e == ELOOP ? std::string("file = a symbolic link, expected a regular file")
                           : "file = unreadable (" + std::string(std::strerror(e)) +
                                 "), expected a regular file this user can read";
    return f;
  }
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    f.refusal = "file = unreadable (" + std::string(std::strerror(errno)) + "), expected a regular file";
  } else if (!S_ISREG(st.st_mode)) {
    f.refusal = "file = " + std::string(kind_of(st.st_mode)) + ", expected a regular file";
  } else if (st.st_uid != geteuid()) {
    f.refusal = "file owner = uid " + std::to_string(st.st_uid) +
                ", expected this gateway's user (uid " + std::to_string(geteuid()) + ")";
  } else if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    f.refusal = "file size = " + std::to_string(st.st_size) + " bytes, expected at most " +
                std::to_string(max_bytes) + " (the largest plan)";
  } else {
    f.bytes.resize(static_cast<std::size_t>(st.st_size) + 1);  // one more: a file that grew
    std::size_t got = 0;
    while (got < f.bytes.size()) {
      const ssize_t n = read(fd, f.bytes.data() + got, f.bytes.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        f.refusal = "file = unreadable (" + std::string(std::strerror(errno)) + ")";
        break;
      }
      if (n == 0) break;
      got += static_cast<std::size_t>(n);
    }
    if (f.refusal.empty() && got > static_cast<std::size_t>(st.st_size)) {
      f.refusal = "file size = growing while read, expected a file written whole (write a "
                  "temporary name in the folder and rename it to next.plan)";
    }
    f.bytes.resize(got);
  }
  close(fd);
  return f;
}

std::string rename_aside(const std::string& from, const std::string& dir, const std::string& stem,
                         const std::string& ext, std::string& error) {
  for (int n = 1; n < 10000; ++n) {
    const std::string name = stem + (n == 1 ? "" : "-" + std::to_string(n)) + ext;
    const std::string to = dir + "/" + name;
    if (renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) {
      return name;
    }
    if (errno != EEXIST) {
      error = std::strerror(errno);
      return "";
    }
  }
  error = "every name from " + stem + ext + " to " + stem + "-9999" + ext + " is taken";
  return "";
}

}  // namespace excite::app
