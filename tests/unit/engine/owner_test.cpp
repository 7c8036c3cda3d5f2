// SPDX-License-Identifier: MIT
// Issue 39 §1–§2, the engine's part: one owner of the setpoints (a quiet interval before arm,
// another master's write while running is a fault) and timeouts on the real clock (lock-step).
// The HIL tests (tests/hil/loop/one_owner_test.cpp, lockstep_waits_test.cpp) run the same
// with the real processes; these pin the rules tick by tick.
#include <cmath>

#include "engine_fixture.hpp"

namespace excite::engine::testing {
namespace {

EngineConfig verified() {
  EngineConfig c = small_config();
  c.verify_readbacks = true;
  for (std::uint32_t i = 0; i < 2; ++i) c.input[i].readback_rel_tol = std::ldexp(1.0, -23);
  return c;
}

class OwnerTest : public EngineTest {};

TEST_F(OwnerTest, TwoQuietReadingsPassAndAReadbackOrEchoThatMovedIsNamed) {
  configure(verified());
  std::array<double, 6> second = field_.values;
  EXPECT_TRUE(engine_.check_quiet(field_.values, second));
  EXPECT_FALSE(engine_.foreign_write().valid);
  second[kY0] += 3.0;  // an output moves on its own: not a write
  EXPECT_TRUE(engine_.check_quiet(field_.values, second));

  second[kRb1] += 1.0;  // setpoint 1's readback moved: another master
  const Status s = engine_.check_quiet(field_.values, second);
  EXPECT_FALSE(s);
  const ForeignWrite& f = engine_.foreign_write();
  EXPECT_TRUE(f.valid && f.at_arm && !f.heartbeat);
  EXPECT_EQ(f.input, 1U);
  EXPECT_EQ(f.expected, 5.0);
  EXPECT_EQ(f.read, 6.0);
}

TEST_F(OwnerTest, AnEchoThatMovedBeforeArmIsAnotherMaster) {
  configure(verified());
  std::array<double, 6> second = field_.values;
  second[kEcho] = 17.0;
  EXPECT_FALSE(engine_.check_quiet(field_.values, second));
  EXPECT_TRUE(engine_.foreign_write().heartbeat);
}

TEST_F(OwnerTest, AnEchoGoingBackWhileRunningIsAForeignWriterAndStopsTheExcitation) {
  configure_arm_start(verified());
  ticks(4);
  ASSERT_EQ(engine_.state(), State::running);
  // Another master wrote heartbeat 40000 between this tick's write and its read.
  engine_.compute();
  field_.values[kEcho] = 40000.0;
  engine_.observe(true, field_.values);
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::foreign_writer);
  EXPECT_TRUE(engine_.foreign_write().heartbeat);
  EXPECT_EQ(engine_.foreign_write().read, 40000.0);
}

TEST_F(OwnerTest, ALaggingEchoIsNotAForeignWriter) {
  configure_arm_start(verified());
  field_.echo = false;  // the echo stands still a few ticks (a slow peer) …
  ticks(2);
  field_.echo = true;  // … then catches up
  ticks(3);
  EXPECT_FALSE(engine_.foreign_write().valid);
  EXPECT_NE(engine_.outcome(), Outcome::foreign_writer);
}

TEST_F(OwnerTest, AReadBeforeTheWriteSeesASetpointWrittenBetweenTicks) {
  configure_arm_start(verified());
  ticks(3);
  engine_.compute();
  std::array<double, 6> before = field_.values;
  before[kRb0] = 77.0;  // written by someone else since the last tick
  engine_.check_before_write(before);
  engine_.observe(true, field_.values);
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::foreign_writer);
  EXPECT_EQ(engine_.foreign_write().input, 0U);
  EXPECT_EQ(engine_.foreign_write().read, 77.0);
}

TEST_F(OwnerTest, AReadBeforeTheWriteShowingAnOlderWriteOfOursIsFine) {
  configure_arm_start(verified());
  ticks(3);
  const double older = last_.setpoint[0];
  ticks(1);
  engine_.compute();
  std::array<double, 6> before = field_.values;
  before[kRb0] = older;  // a lagging readback: a value this gateway wrote
  engine_.check_before_write(before);
  engine_.observe(true, field_.values);
  EXPECT_FALSE(engine_.foreign_write().valid);
}

TEST_F(OwnerTest, AReadbackFasterThanItsLagShowsANewerWriteOfOursAndIsFine) {
  // CAN: the peer sends its readbacks on its own cycle, so a reading may already hold this
  // tick's write where readback_lag_ticks = 3 compares the write of two ticks before. The
  // mismatch is counted (verified writes); it is not another master.
  EngineConfig c = verified();
  c.readback_lag_ticks = 3;
  c.readback_mismatch_limit = 100;
  configure(c);
  arm();
  ticks(3);  // armed: the baseline written and read back
  engine_.command(Command::start);
  ticks(6);  // the first move reads back while the baseline is compared
  EXPECT_GT(engine_.readback_mismatches(), 0U);
  EXPECT_FALSE(engine_.foreign_write().valid);
  EXPECT_EQ(engine_.state(), State::running);

  // A value this gateway never wrote, with the write compared held: another master.
  engine_.command(Command::suspend);
  ticks(4);  // the setpoints stand still at the baseline
  engine_.compute();
  field_.values[kRb1] = 33.0;
  engine_.observe(true, field_.values);
  EXPECT_EQ(engine_.outcome(), Outcome::foreign_writer);
  EXPECT_EQ(engine_.foreign_write().read, 33.0);
}

TEST_F(OwnerTest, LockstepTimeoutsEndOnTheRealClockAndFailedExchangesAddNoTick) {
  EngineConfig c = verified();
  c.suspend_timeout_ticks = 5;
  c.suspend_timeout_ns = 1'000'000'000;  // 1 s
  c.confirm_timeout_ticks = 5;
  c.confirm_timeout_ns = 1'000'000'000;
  configure_arm_start(c);
  std::int64_t now = 0;
  engine_.set_real_time(now);
  ticks(2);
  field_.ok = false;  // the peer is gone: every exchange fails, 250 ms apart
  for (int i = 0; i < 30 && engine_.state() != State::aborted; ++i) {
    now += 250'000'000;
    engine_.set_real_time(now);
    tick();
  }
  // 5 failed ticks would have been the tick timeout; they add none: the real 1 s ends it.
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_on_timeout);
  EXPECT_GE(now, 1'000'000'000 + 2 * 250'000'000LL);  // comm loss after 2 failures, then 1 s
  for (int i = 0; i < 30 && !finished(engine_.state()); ++i) {
    now += 250'000'000;
    engine_.set_real_time(now);
    tick();
  }
  EXPECT_EQ(engine_.state(), State::safe_unconfirmed);
}

TEST_F(OwnerTest, ARefusalIsNotFlaggedCommLost) {
  configure_arm_start(verified());
  ticks(2);
  engine_.compute();
  engine_.observe(false, field_.values, /*refused=*/true);
  EXPECT_EQ(engine_.flags() & runlog::kCommLost, 0U);
  EXPECT_EQ(engine_.failed_exchanges(), 1U);
  engine_.compute();
  engine_.observe(false, field_.values);  // a real failure is
  EXPECT_NE(engine_.flags() & runlog::kCommLost, 0U);
}

}  // namespace
}  // namespace excite::engine::testing
