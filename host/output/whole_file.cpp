// SPDX-License-Identifier: MIT
#include "host/output/whole_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <vector>

namespace excite::host {
namespace {

namespace fs = std::filesystem;

// Read once before main (no other thread yet): umask() can only be read by setting it.
const mode_t process_umask = [] {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}();

// The final target of a chain of symbolic links (the path itself when it is none).
fs::path follow_links(const fs::path& path) {
  fs::path p = path;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return p;
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw std::runtime_error(path.string() +
                           ": cannot be written (too many levels of symbolic links)");
}

// The descriptor N when `p` names one of this process's own descriptors: /dev/stdin,
// /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N, /proc/thread-self/fd/N or
// /proc/PID/fd/N with this process's PID.
std::optional<int> own_descriptor_name(const fs::path& p) {
  const std::string s = p.lexically_normal().string();
  if (s == "/dev/stdin") return 0;
  if (s == "/dev/stdout") return 1;
  if (s == "/dev/stderr") return 2;
  const std::string self_pid = "/proc/" + std::to_string(::getpid()) + "/fd/";
  for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"),
                                    std::string("/proc/thread-self/fd/"), self_pid}) {
    if (s.rfind(prefix, 0) != 0 || s.size() == prefix.size() || s.size() > prefix.size() + 9)
      continue;
    const std::string digits = s.substr(prefix.size());
    if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
    return std::stoi(digits);
  }
  return std::nullopt;
}

// The descriptor the name reaches through a chain of symbolic links, if one of the links
// (or the name itself) is one of the names above.
std::optional<int> own_descriptor(const fs::path& path) {
  fs::path p = fs::absolute(path);
  for (int hops = 0; hops < 40; ++hops) {
    if (const auto fd = own_descriptor_name(p)) return fd;
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return std::nullopt;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return std::nullopt;
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  return std::nullopt;
}

}  // namespace

bool writes_to_stdout(const fs::path& path) {
  if (path == "-") return true;
  if (own_descriptor(path) == 1) return true;
  struct stat out {
  }, named{};
  return ::fstat(STDOUT_FILENO, &out) == 0 && ::stat(path.c_str(), &named) == 0 &&
         out.st_dev == named.st_dev && out.st_ino == named.st_ino;
}

WholeFile::WholeFile(const fs::path& path) : path_(path) {
  std::signal(SIGXFSZ, SIG_IGN);
  if (path_ == "-") {
    is_stdout_ = true;
    stream_ = stdout;
    return;
  }
  // One of our own descriptors (/dev/stdout, /dev/fd/N, …): written through a copy of the
  // descriptor, so `>> journal.log` appends, and a pipe or socket works.
  if (const auto fd = own_descriptor(path_)) {
    const int copy = ::fcntl(*fd, F_DUPFD_CLOEXEC, 3);
    if (copy < 0) fail(std::strerror(errno));
    stream_ = ::fdopen(copy, "w");
    if (stream_ == nullptr) {
      const int error = errno;
      ::close(copy);
      fail(std::strerror(error));
    }
    return;
  }
  // What the name is decides, as stat() sees it through any links.
  struct stat st {};
  const bool exists = ::stat(path_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) fail("it is a directory");
  if (exists && !S_ISREG(st.st_mode)) {  // device, FIFO, socket: write through, never replace
    stream_ = std::fopen(path_.c_str(), "w");
    if (stream_ == nullptr) fail(std::strerror(errno));
    return;
  }
  target_ = follow_links(path_);
  const fs::path folder = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  const std::string pattern = (folder / ("." + target_.filename().string() + ".XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkostemp(name.data(), O_CLOEXEC);
  if (fd < 0) fail(std::strerror(errno));
  temporary_ = name.data();
  const mode_t mode = exists ? (st.st_mode & 07777) : (0666 & ~process_umask);
  if (::fchmod(fd, mode) != 0 || (stream_ = ::fdopen(fd, "w")) == nullptr) {
    const int error = errno;
    ::close(fd);
    fail(std::strerror(error));
  }
}

WholeFile::~WholeFile() {
  discard();
}

void WholeFile::discard() noexcept {
  if (stream_ != nullptr && !is_stdout_) std::fclose(stream_);
  stream_ = nullptr;
  if (!temporary_.empty()) {
    std::error_code ignored;
    fs::remove(temporary_, ignored);
    temporary_.clear();
  }
}

void WholeFile::fail(const std::string& reason) {
  discard();
  throw std::runtime_error(path_.string() + ": cannot be written (" + reason + ")");
}

void WholeFile::commit() {
  if (stream_ == nullptr) throw std::logic_error(path_.string() + ": committed twice");
  errno = 0;
  if (std::fflush(stream_) != 0 || std::ferror(stream_) != 0) {
    fail(errno != 0 ? std::strerror(errno) : "write error");
  }
  if (is_stdout_) {
    stream_ = nullptr;
    return;
  }
  if (temporary_.empty()) {  // written through
    const int closed = std::fclose(stream_);
    stream_ = nullptr;
    if (closed != 0) fail(std::strerror(errno));
    return;
  }
  if (::fsync(::fileno(stream_)) != 0) fail(std::strerror(errno));
  const int closed = std::fclose(stream_);
  stream_ = nullptr;
  if (closed != 0) fail(std::strerror(errno));
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) fail(std::strerror(errno));
  temporary_.clear();
}

void WholeFile::write(std::string_view bytes) {
  if (stream_ == nullptr) throw std::logic_error(path_.string() + ": written after commit");
  errno = 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), stream_) != bytes.size() ||
      std::fflush(stream_) != 0) {
    fail(errno != 0 ? std::strerror(errno) : "write error");
  }
}

void write_whole_file(const fs::path& path, std::string_view bytes) {
  WholeFile file(path);
  file.write(bytes);
  file.commit();
}

}  // namespace excite::host
