// SPDX-License-Identifier: MIT
#include "hal/posix/posix_clock.hpp"

#include <cerrno>
#include <ctime>

namespace excite::hal {

namespace {
constexpr long nanoseconds_per_second = 1'000'000'000L;
}  // namespace

Nanoseconds PosixClock::now() const noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);  // cannot fail for CLOCK_MONOTONIC with valid ts
  return Nanoseconds{static_cast<std::int64_t>(ts.tv_sec) * nanoseconds_per_second + ts.tv_nsec};
}

void PosixClock::sleep_until(Nanoseconds deadline) noexcept {
  if (deadline.count() <= 0) {
    return;
  }
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline.count() / nanoseconds_per_second);
  ts.tv_nsec = static_cast<long>(deadline.count() % nanoseconds_per_second);
  // clock_nanosleep returns the error number (not -1/errno); EINTR: a signal arrived
  // before the deadline; sleep again to the same absolute deadline.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace excite::hal
