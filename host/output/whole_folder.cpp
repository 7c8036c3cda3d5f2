// SPDX-License-Identifier: MIT
#include "host/output/whole_folder.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/output/folder_marker.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void refuse(const fs::path& path, const std::string& reason) {
  throw std::runtime_error(path.string() + ": cannot be written (" + reason + ")");
}

// Read once before main (no other thread yet): umask() can only be read by setting it.
const mode_t process_umask = [] {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return mask;
}();

}  // namespace

WholeFolder::WholeFolder(const fs::path& path, bool overwrite, std::string kind)
    : path_(path), kind_(std::move(kind)) {
  if (path.empty()) refuse(path, "an empty name");
  std::error_code ec;
  target_ = fs::absolute(path, ec).lexically_normal();
  if (target_.filename().empty()) target_ = target_.parent_path();  // "dir/" is "dir"
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {
    target_ = fs::weakly_canonical(target_, ec);
    if (ec) refuse(path, ec.message());
  }
  if (target_ == target_.root_path()) refuse(path, "the root folder");
  const fs::file_status st = fs::status(target_, ec);
  mode_t mode = 0777 & ~process_umask;
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) refuse(path, "it is not a folder");
    if (!fs::is_empty(target_, ec) && !overwrite) {
      const std::string foreign = foreign_entry(target_, kind_);
      if (!foreign.empty()) {
        refuse(path, "a folder with other files: " + foreign +
                         ", expected a new or empty folder, a previous " + kind_ +
                         "'s holding only what it wrote, or --overwrite to replace it whole");
      }
    }
    struct stat info {};
    if (::stat(target_.c_str(), &info) == 0) mode = info.st_mode & 07777;
  }
  const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) refuse(path, ec.message());
  const std::string pattern = (parent / ("." + target_.filename().string() + ".XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (::mkdtemp(name.data()) == nullptr) refuse(path, std::strerror(errno));
  staging_ = name.data();
  ::chmod(staging_.c_str(), mode);
}

WholeFolder::~WholeFolder() {
  if (!staging_.empty()) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void WholeFolder::commit() {
  if (staging_.empty()) throw std::logic_error(path_.string() + ": committed twice");
  write_folder_marker(staging_, kind_, folder_entries(staging_));
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(target_, ec))) {
    if (::rename(staging_.c_str(), target_.c_str()) != 0) refuse(path_, std::strerror(errno));
    staging_.clear();
    return;
  }
  // Swap in one step; the previous folder ends up under the temporary name.
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0) {
    if (errno != EINVAL && errno != ENOSYS) refuse(path_, std::strerror(errno));
    // A file system without the exchange: two renames, the old folder kept until the new
    // one is in place.
    const fs::path old = staging_.string() + ".old";
    if (::rename(target_.c_str(), old.c_str()) != 0) refuse(path_, std::strerror(errno));
    if (::rename(staging_.c_str(), target_.c_str()) != 0) {
      const int error = errno;
      ::rename(old.c_str(), target_.c_str());
      refuse(path_, std::strerror(error));
    }
    fs::remove_all(old, ec);
    staging_.clear();
    return;
  }
  fs::remove_all(staging_, ec);  // the previous folder
  staging_.clear();
}

}  // namespace excite::host
