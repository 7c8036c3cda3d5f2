// SPDX-License-Identifier: MIT
#pragma once
// CPU seconds (user + system) of this process's threads and of the children it has waited
// for (gnuplot, excite-gateway, excite-plant): what a bench that starts programs costs,
// less sensitive than wall time to other jobs on the machine. Included by relative path.

#include <sys/resource.h>

namespace excite::bench {

inline double cpu_seconds_with_children() {
  rusage self{};
  rusage children{};
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &children);
  const auto s = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
  };
  return s(self.ru_utime) + s(self.ru_stime) + s(children.ru_utime) + s(children.ru_stime);
}

}  // namespace excite::bench
