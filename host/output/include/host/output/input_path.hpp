// SPDX-License-Identifier: MIT
#pragma once
// Input files named on the command line: a folder is refused with its path, before a stream
// reports "basic_filebuf::underflow … Is a directory" without one.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace excite::host {

inline void refuse_directory(const std::filesystem::path& path, const std::string& expected) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw std::invalid_argument(path.string() + ": is a directory, expected " + expected);
  }
}

}  // namespace excite::host
