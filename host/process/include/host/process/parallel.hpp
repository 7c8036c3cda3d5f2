// SPDX-License-Identifier: MIT
#pragma once
// Independent tasks on a few threads. Each task writes only its own result slot, so the
// results do not depend on the number of threads or on the order the tasks finish in.

#include <functional>

namespace excite::host {

/// Calls task(i) for every i in [0, count) on min(threads, count) threads (threads ≥ 1;
/// 1 runs them in order on the caller's thread). If tasks throw, the exception of the
/// lowest i is rethrown after every started task has finished.
void parallel_for(int count, int threads, const std::function<void(int)>& task);

}  // namespace excite::host
