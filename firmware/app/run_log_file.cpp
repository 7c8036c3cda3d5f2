// SPDX-License-Identifier: MIT
#include "firmware/app/run_log_file.hpp"

#include <utility>

namespace excite::app {

RunLogFile::RunLogFile(std::string path)
    : path_(std::move(path)), file_(std::fopen(path_.c_str(), "w")), opened_(file_ != nullptr) {}

RunLogFile::~RunLogFile() {
  close();
  if (opened_ && !keep_) std::remove(path_.c_str());
}

bool RunLogFile::close() noexcept {
  if (file_ == nullptr) return true;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  return closed;
}

}  // namespace excite::app
