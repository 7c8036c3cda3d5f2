// SPDX-License-Identifier: MIT
#include "host/output/own_entries.hpp"

#include <stdio.h>
#include <stdlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>

#include "host/output/folder_marker.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void refuse(const fs::path& path, const std::string& reason) {
  throw std::runtime_error(path.string() + ": cannot be written (" + reason + ")");
}

bool listed(const std::optional<std::vector<std::string>>& marked, const std::string& entry) {
  return marked && std::binary_search(marked->begin(), marked->end(), entry);
}

}  // namespace

OwnEntries::OwnEntries(const fs::path& folder, bool overwrite, std::string kind,
                       std::vector<std::string> names)
    : path_(folder), kind_(std::move(kind)), names_(std::move(names)) {
  if (folder.empty()) refuse(folder, "an empty name");
  std::error_code ec;
  target_ = fs::absolute(folder, ec).lexically_normal();
  if (target_.filename().empty()) target_ = target_.parent_path();  // "dir/" is "dir"
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {
    target_ = fs::weakly_canonical(target_, ec);
    if (ec) refuse(folder, ec.message());
  }
  const fs::file_status st = fs::status(target_, ec);
  if (fs::exists(st) && !fs::is_directory(st)) refuse(folder, "it is not a folder");
  if (fs::exists(st) && !overwrite) {
    const std::optional<std::vector<std::string>> marked = marked_entries(target_, kind_);
    const std::string expected = ", expected a new folder, one without it, a previous " + kind_ +
                                 "'s output, or --overwrite to replace it";
    for (const std::string& name : names_) {
      const fs::file_status entry = fs::symlink_status(target_ / name, ec);
      if (!fs::exists(entry)) continue;
      const bool folder_entry = fs::is_directory(entry);
      if (!listed(marked, folder_entry ? name + "/" : name))
        refuse(folder, name + " is not a file excite wrote" + expected);
      if (!folder_entry) continue;
      for (const std::string& inside : folder_entries(target_ / name)) {
        if (!listed(marked, name + "/" + inside))
          refuse(folder, name + "/" + inside + " is not a file excite wrote" + expected);
      }
    }
  }
  fs::create_directories(target_, ec);
  if (ec) refuse(folder, ec.message());
  const std::string pattern = (target_ / (".excite-" + kind_ + ".XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  std::replace(name.begin() + static_cast<long>(target_.string().size()), name.end(), ' ', '-');
  name.push_back('\0');
  if (::mkdtemp(name.data()) == nullptr) refuse(folder, std::strerror(errno));
  staging_ = name.data();
}

OwnEntries::~OwnEntries() {
  if (!staging_.empty()) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void OwnEntries::commit() {
  if (staging_.empty()) throw std::logic_error(path_.string() + ": committed twice");
  std::error_code ec;
  std::vector<std::string> written;
  for (const std::string& name : names_) {
    const fs::path made = staging_ / name;
    if (!fs::exists(fs::symlink_status(made, ec))) continue;
    const fs::path place = target_ / name;
    fs::remove_all(place, ec);  // a link is removed, never followed
    if (ec) refuse(path_, place.string() + ": " + ec.message());
    if (::rename(made.c_str(), place.c_str()) != 0) refuse(path_, std::strerror(errno));
  }
  for (const std::string& entry : folder_entries(target_)) {
    for (const std::string& name : names_) {
      if (entry == name || entry == name + "/" || entry.rfind(name + "/", 0) == 0)
        written.push_back(entry);
    }
  }
  write_folder_marker(target_, kind_, written);
  fs::remove_all(staging_, ec);
  staging_.clear();
}

}  // namespace excite::host
