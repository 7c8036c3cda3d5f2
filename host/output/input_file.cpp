// SPDX-License-Identifier: MIT
#include "host/output/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "base/config/document.hpp"

namespace excite::host {
namespace {

// Closes the descriptor on every path out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string read_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes,
                            const std::string& what) {
  const std::string name = path.string();
  const Descriptor file{::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) {
    throw std::invalid_argument(name + ": cannot be read (" + std::strerror(errno) +
                                "), expected " + what);
  }
  struct stat info {};
  if (::fstat(file.fd, &info) != 0) {
    throw std::invalid_argument(name + ": cannot be read (" + std::strerror(errno) +
                                "), expected " + what);
  }
  if (!S_ISREG(info.st_mode)) {
    throw std::invalid_argument(name + ": file type = " + config::file_type_name(info.st_mode) +
                                ", expected a regular file (" + what + ")");
  }
  const auto too_large = [&](std::uintmax_t size, const char* at_least) {
    return std::invalid_argument(name + ": size = " + at_least + std::to_string(size) +
                                 " bytes, expected at most " + std::to_string(max_bytes) +
                                 " bytes (" + what + ")");
  };
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes)
    throw too_large(static_cast<std::uintmax_t>(info.st_size), "");
  std::string bytes;
  bytes.resize(static_cast<std::size_t>(info.st_size));
  std::size_t got = 0;
  for (;;) {
    if (got == bytes.size()) {
      if (got > max_bytes) throw too_large(got, "over ");
      // It grew while read (or stat said 0, as /proc does): at most to one byte past the bound.
      bytes.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(
          std::max<std::uintmax_t>(bytes.size() * 2, 4096), max_bytes + 1)));
    }
    const ssize_t n = ::read(file.fd, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw std::invalid_argument(name + ": cannot be read (" + std::strerror(errno) +
                                  "), expected " + what);
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) throw too_large(got, "over ");
  bytes.resize(got);
  return bytes;
}

}  // namespace excite::host
