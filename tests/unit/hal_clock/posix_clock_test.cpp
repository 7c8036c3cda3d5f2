// SPDX-License-Identifier: MIT
// The real clock: monotonic, never wakes before an absolute deadline. (Lateness is a
// property of the machine and measured, never asserted, here.)
#include <gtest/gtest.h>

#include <chrono>

#include "excite/hal/periodic.hpp"
#include "hal/posix/posix_clock.hpp"

using excite::hal::Nanoseconds;
using excite::hal::PeriodicSchedule;
using excite::hal::PosixClock;

TEST(PosixClock, NeverGoesBackwards) {
  PosixClock clock;
  Nanoseconds previous = clock.now();
  for (int i = 0; i < 10000; ++i) {
    const Nanoseconds now = clock.now();
    ASSERT_GE(now, previous);
    previous = now;
  }
}

TEST(PosixClock, SleepUntilNeverReturnsBeforeTheDeadline) {
  PosixClock clock;
  for (int i = 0; i < 20; ++i) {
    const Nanoseconds deadline = clock.now() + std::chrono::microseconds(500);
    clock.sleep_until(deadline);
    EXPECT_GE(clock.now(), deadline);
  }
}

TEST(PosixClock, SleepUntilThePastReturns) {
  PosixClock clock;
  const Nanoseconds before = clock.now();
  clock.sleep_until(before - std::chrono::seconds(1));
  EXPECT_GE(clock.now(), before);
}

TEST(PosixClock, PeriodicScheduleTicksOnTheGrid) {
  PosixClock clock;
  PeriodicSchedule schedule(clock, std::chrono::milliseconds(1));
  const Nanoseconds first = schedule.wait_next();
  for (std::int64_t k = 1; k <= 20; ++k) {
    const Nanoseconds tick = schedule.wait_next();
    // Grid points only: first + n periods, whether or not the machine caused overruns.
    EXPECT_EQ((tick - first) % std::chrono::milliseconds(1), Nanoseconds{0});
    EXPECT_GE(clock.now(), tick);
  }
}
