// SPDX-License-Identifier: MIT
#include "firmware/app/run_identity.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

namespace excite::app {

namespace {

bool is_hex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
}

}  // namespace

std::string new_run_id() {
  std::array<std::uint8_t, 8> bytes{};
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = getrandom(bytes.data() + got, bytes.size() - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got < bytes.size()) {  // no random source: the pid and the time still tell runs apart
    std::uint64_t mix = static_cast<std::uint64_t>(getpid());
    mix *= std::uint64_t{0x9E3779B97F4A7C15};
    mix ^= static_cast<std::uint64_t>(time(nullptr));
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      bytes[i] = static_cast<std::uint8_t>(mix >> (8 * i));
    }
  }
  std::string id;
  char two[3];
  for (std::uint8_t b : bytes) {
    std::snprintf(two, sizeof two, "%02x", static_cast<unsigned>(b));
    id += two;
  }
  return id;
}

std::string run_tag(std::string_view id) {
  return "run " + std::string(id);
}

std::optional<std::string> run_named_in(std::string_view text) {
  for (std::size_t at = text.find("run "); at != std::string_view::npos;
       at = text.find("run ", at + 1)) {
    const std::size_t from = at + 4;
    if (text.size() < from + 16) break;
    bool ok = true;
    for (std::size_t i = 0; i < 16 && ok; ++i) ok = is_hex(text[from + i]);
    if (ok && (text.size() == from + 16 || !is_hex(text[from + 16]))) {
      return std::string(text.substr(from, 16));
    }
  }
  return std::nullopt;
}

RunMarker::~RunMarker() {
  if (path_.empty()) return;
  std::ifstream in(path_);
  std::string first;
  std::getline(in, first);
  if (first == run_tag(id_)) unlink(path_.c_str());
}

std::string RunMarker::write(const std::string& dir, const std::string& id,
                             const std::string& log_path) {
  const std::string path = dir + "/" + kRunMarkerName;
  const std::string tmp = dir + "/." + kRunMarkerName + ".tmp";
  std::ostringstream text;
  text << run_tag(id) << "\npid " << getpid() << "\nlog " << log_path << "\n";
  const std::string body = text.str();
  unlink(tmp.c_str());  // a link planted there is removed, never followed
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    return tmp + " = not writable (" + std::string(std::strerror(errno)) +
           "), expected the gateway's run marker";
  }
  const bool whole = ::write(fd, body.data(), body.size()) == static_cast<ssize_t>(body.size());
  close(fd);
  if (!whole || rename(tmp.c_str(), path.c_str()) != 0) {
    unlink(tmp.c_str());
    return path + " = not written (" + std::string(std::strerror(errno)) +
           "), expected the gateway's run marker";
  }
  path_ = path;
  id_ = id;
  return "";
}

}  // namespace excite::app
