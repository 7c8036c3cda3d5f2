// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include "excite/hal/virtual_clock.hpp"

using excite::hal::Nanoseconds;
using excite::hal::VirtualClock;

TEST(VirtualClock, TimeStandsStillUntilSomeoneSleepsOrAdvances) {
  VirtualClock clock(Nanoseconds{5});
  EXPECT_EQ(clock.now(), Nanoseconds{5});
  EXPECT_EQ(clock.now(), Nanoseconds{5});
}

TEST(VirtualClock, SleepUntilJumpsToTheDeadline) {
  VirtualClock clock;
  clock.sleep_until(Nanoseconds{1'000'000'000});
  EXPECT_EQ(clock.now(), Nanoseconds{1'000'000'000});
}

TEST(VirtualClock, SleepUntilThePastLeavesTimeAlone) {
  VirtualClock clock(Nanoseconds{100});
  clock.sleep_until(Nanoseconds{50});
  EXPECT_EQ(clock.now(), Nanoseconds{100});
}

TEST(VirtualClock, AdvanceAddsTheStep) {
  VirtualClock clock(Nanoseconds{100});
  clock.advance(Nanoseconds{23});
  EXPECT_EQ(clock.now(), Nanoseconds{123});
  clock.advance(Nanoseconds{-5});  // time never goes back
  EXPECT_EQ(clock.now(), Nanoseconds{123});
}
