// SPDX-License-Identifier: MIT
#pragma once
// The time stamped into new plan files: SOURCE_DATE_EPOCH when set (reproducible builds of
// plans), else now.

#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <stdexcept>
#include <string>

namespace excite::host::cli {

inline std::uint64_t creation_time() {
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const unsigned long long value = std::strtoull(epoch, &end, 10);
    if (end == epoch || *end != '\0') {
      throw std::invalid_argument(std::string("SOURCE_DATE_EPOCH = \"") + epoch +
                                  "\", expected seconds since 1970 as a whole number");
    }
    return value;
  }
  return static_cast<std::uint64_t>(std::time(nullptr));
}

}  // namespace excite::host::cli
