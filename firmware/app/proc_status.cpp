// SPDX-License-Identifier: MIT
#include "firmware/app/proc_status.hpp"

#include <fstream>

namespace excite::app {

std::string memory_status() {
  std::ifstream in("/proc/self/status");
  std::string line;
  std::string rss;
  std::string hwm;
  auto value = [](const std::string& l) {
    const auto start = l.find_first_not_of(" \t", 6);
    return start == std::string::npos ? std::string() : l.substr(start);
  };
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) rss = value(line);
    if (line.rfind("VmHWM:", 0) == 0) hwm = value(line);
  }
  if (rss.empty()) return "";
  return "VmRSS " + rss + ", VmHWM " + hwm;
}

}  // namespace excite::app
