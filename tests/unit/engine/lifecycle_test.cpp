// SPDX-License-Identifier: MIT
// The lifecycle: configured → armed → running → completed → returning → safe, and abort.
#include "engine_fixture.hpp"

namespace excite::engine::testing {

TEST_F(EngineTest, ConfiguredWritesNothing) {
  configure();
  EXPECT_EQ(engine_.state(), State::configured);
  EXPECT_FALSE(tick().write);
  EXPECT_FALSE(tick().write);
}

TEST_F(EngineTest, ArmTakesTheBaselineFromTheReadbacks) {
  configure();
  arm();
  EXPECT_EQ(engine_.state(), State::armed);
  EXPECT_EQ(engine_.baseline(0), 40.0);
  EXPECT_EQ(engine_.baseline(1), 5.0);
  EXPECT_EQ(engine_.value_baseline(kY0), 100.0);
}

TEST_F(EngineTest, ArmedHoldsTheBaselineWithAHeartbeat) {
  configure();
  arm();
  const TickOutput first = tick();
  const TickOutput second = tick();
  EXPECT_TRUE(first.write);
  EXPECT_EQ(first.setpoint[0], 40.0);
  EXPECT_EQ(first.setpoint[1], 5.0);
  EXPECT_EQ(static_cast<std::uint16_t>(second.heartbeat - first.heartbeat), 1);
  EXPECT_EQ(engine_.state(), State::armed);
}

TEST_F(EngineTest, RunningStreamsBaselinePlusEveryTableRowInOrder) {
  configure_arm_start();
  for (std::uint32_t k = 0; k < kRows; ++k) {
    const TickOutput& out = tick();
    EXPECT_EQ(engine_.state(), State::running);
    EXPECT_EQ(engine_.row(), k);
    EXPECT_EQ(out.setpoint[0], 40.0 + (k + 1.0));
    EXPECT_EQ(out.setpoint[1], 5.0 - (k + 1.0));
  }
}

TEST_F(EngineTest, CompletedTableReturnsToBaselineAndEndsSafe) {
  EngineConfig c = small_config();
  c.ramp_ticks = 4;
  configure_arm_start(c);
  ticks(4 + kRows);  // ramp-in overlaps the first rows; then the table
  tick();            // the tick after the last row
  EXPECT_EQ(engine_.outcome(), Outcome::completed);
  int guard = 0;
  while (engine_.state() != State::safe && guard++ < 100) tick();
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(last_.setpoint[0], 40.0);
  EXPECT_EQ(last_.setpoint[1], 5.0);
  EXPECT_LT(guard, 10);
}

TEST_F(EngineTest, CompletedIsVisibleForOneTickThenReturning) {
  configure_arm_start();
  ticks(kRows);
  tick();
  EXPECT_EQ(engine_.state(), State::completed);
  tick();
  EXPECT_TRUE(engine_.state() == State::returning || engine_.state() == State::safe);
}

TEST_F(EngineTest, AbortBeforeArmGoesSafeWithoutWriting) {
  configure();
  engine_.command(Command::abort);
  EXPECT_FALSE(tick().write);
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_by_operator);
}

TEST_F(EngineTest, AbortWhileRunningRampsOutToSafe) {
  EngineConfig c = small_config();
  c.ramp_ticks = 2;
  configure_arm_start(c);
  ticks(5);
  engine_.command(Command::abort);
  tick();
  EXPECT_EQ(engine_.state(), State::aborted);
  ticks(3);
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_by_operator);
  EXPECT_EQ(last_.setpoint[0], 40.0);
}

TEST_F(EngineTest, StartIsIgnoredUnlessArmed) {
  configure();
  engine_.command(Command::start);
  tick();
  EXPECT_EQ(engine_.state(), State::configured);
}

TEST_F(EngineTest, ArmRefusesABaselineOutsideTheSetpointLimits) {
  configure();
  field_.values[kRb0] = 120.0;  // max is 100
  const Status s = engine_.arm(field_.values);
  EXPECT_FALSE(s);
  EXPECT_STREQ(s.message(),
               "input[0] baseline = 120 (read back from value[2]), expected within [0, 100]");
  EXPECT_EQ(engine_.state(), State::configured);
}

TEST_F(EngineTest, ArmRefusesWhenBaselinePlusTableWouldLeaveTheLimits) {
  configure();
  field_.values[kRb0] = 95.0;  // 95 + 8 > 100
  const Status s = engine_.arm(field_.values);
  EXPECT_FALSE(s);
  EXPECT_STREQ(s.message(),
               "input[0] baseline + table = [95, 103], expected within [0, 100] (baseline 95)");
}

TEST_F(EngineTest, ArmRefusesANonFiniteValue) {
  configure();
  field_.values[kY1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(engine_.arm(field_.values));
}

TEST_F(EngineTest, ConfigureRefusesATableOfAnotherWidth) {
  EngineConfig c = small_config();
  c.inputs = 1;
  c.input[0].readback = static_cast<std::int32_t>(kRb0);
  const Status s = engine_.configure(c, table());
  EXPECT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("expected 1 channels"), std::string::npos);
}

}  // namespace excite::engine::testing
