// SPDX-License-Identifier: MIT
// The periodic schedule on a virtual clock: no drift, overruns counted, no catch-up burst.
#include <gtest/gtest.h>

#include <cstdint>

#include "excite/hal/periodic.hpp"
#include "excite/hal/virtual_clock.hpp"

using excite::hal::Nanoseconds;
using excite::hal::PeriodicSchedule;
using excite::hal::VirtualClock;

namespace {
constexpr Nanoseconds period{10'000'000};  // 10 ms
}

TEST(PeriodicSchedule, TicksLandOnTheGridWhateverTheWorkTakes) {
  VirtualClock clock(Nanoseconds{3});
  PeriodicSchedule schedule(clock, period);
  for (std::int64_t k = 1; k <= 1000; ++k) {
    const Nanoseconds tick = schedule.wait_next();
    EXPECT_EQ(tick, Nanoseconds{3} + k * period);
    EXPECT_EQ(clock.now(), tick);
    clock.advance(Nanoseconds{(k * 7919) % 9'000'000});  // work: 0..9 ms, varying
  }
  EXPECT_EQ(schedule.overruns(), 0U);
  EXPECT_EQ(schedule.ticks(), 1000U);
}

TEST(PeriodicSchedule, AnOverrunSkipsTheMissedTicksAndCountsThem) {
  VirtualClock clock;
  PeriodicSchedule schedule(clock, period);
  EXPECT_EQ(schedule.wait_next(), period);
  clock.advance(period * 5 / 2);  // work takes 2.5 periods: deadlines 2 and 3 are missed
  const Nanoseconds next = schedule.wait_next();
  EXPECT_EQ(next, 4 * period);
  EXPECT_EQ(schedule.overruns(), 2U);
}

TEST(PeriodicSchedule, AfterAnOverrunTheLoopDoesNotBurst) {
  VirtualClock clock;
  PeriodicSchedule schedule(clock, period);
  schedule.wait_next();
  clock.advance(period * 10 + Nanoseconds{1});
  const Nanoseconds resumed = schedule.wait_next();
  const Nanoseconds following = schedule.wait_next();
  EXPECT_EQ(following - resumed, period);  // one period apart, not back to back
  EXPECT_EQ(schedule.overruns(), 10U);
}

TEST(PeriodicSchedule, WorkEndingExactlyOnTheDeadlineIsNotAnOverrun) {
  VirtualClock clock;
  PeriodicSchedule schedule(clock, period);
  schedule.wait_next();
  clock.advance(period);
  EXPECT_EQ(schedule.wait_next(), 2 * period);
  EXPECT_EQ(schedule.overruns(), 0U);
}
