// SPDX-License-Identifier: MIT
#include "host/output/whole_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
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

}  // namespace

WholeFile::WholeFile(const fs::path& path) : path_(path) {
  std::signal(SIGXFSZ, SIG_IGN);
  if (path_ == "-") {
    is_stdout_ = true;
    stream_ = stdout;
    return;
  }
  target_ = follow_links(path_);
  struct stat st {};
  const bool exists = ::stat(target_.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) fail("it is a directory");
  if (exists && !S_ISREG(st.st_mode)) {  // device, FIFO, socket: write through, never replace
    stream_ = std::fopen(target_.c_str(), "w");
    if (stream_ == nullptr) fail(std::strerror(errno));
    return;
  }
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
