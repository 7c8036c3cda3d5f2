// SPDX-License-Identifier: MIT
#pragma once
// Real-time set-up of the calling thread: SCHED_FIFO at `priority` and mlockall when
// permitted, and a pre-faulted stack (256 KiB). Each step that is not permitted (no CAP_SYS_NICE,
// RLIMIT_MEMLOCK) is reported in the result's warnings and the gateway continues.

#include <string>
#include <vector>

namespace excite::app {

struct RealtimeResult {
  bool fifo = false;    // SCHED_FIFO active
  bool locked = false;  // mlockall(MCL_CURRENT | MCL_FUTURE) succeeded
  std::vector<std::string> warnings;
};

/// priority 0: leave the scheduling policy alone (still locks memory and pre-faults).
RealtimeResult make_realtime(int priority);

}  // namespace excite::app
