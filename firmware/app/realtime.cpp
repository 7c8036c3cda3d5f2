// SPDX-License-Identifier: MIT
#include "firmware/app/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace excite::app {

namespace {

// Touches kPrefaultBytes of stack so the pages are mapped (and locked) before the first tick.
constexpr std::size_t kPrefaultBytes = 256 * 1024;

__attribute__((noinline)) void prefault_stack() {
  unsigned char block[kPrefaultBytes];
  for (std::size_t i = 0; i < kPrefaultBytes; i += 4096) {
    *static_cast<volatile unsigned char*>(block + i) = 0;
  }
  asm volatile("" : : "r"(block) : "memory");  // keep the block: its pages are the point
}

}  // namespace

RealtimeResult make_realtime(int priority) {
  RealtimeResult result;
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    result.locked = true;
  } else {
    result.warnings.push_back(std::string("mlockall failed (") + std::strerror(errno) +
                              "): memory may be paged; continuing");
  }
  if (priority > 0) {
    sched_param param{};
    param.sched_priority = priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (rc == 0) {
      result.fifo = true;
    } else {
      result.warnings.push_back("SCHED_FIFO priority " + std::to_string(priority) +
                                " not permitted (" + std::strerror(rc) +
                                "): running with the default scheduler; continuing");
    }
  }
  prefault_stack();
  return result;
}

}  // namespace excite::app
