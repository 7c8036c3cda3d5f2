// SPDX-License-Identifier: MIT
// Test limits (suspend, resume with hysteresis and dwell, abort on timeout), communication
// loss (failed exchanges, stale heartbeat echo; hold or ramp), operator commands.
#include "engine_fixture.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine::testing {

TEST_F(EngineTest, ExcursionSuspendsAndHoldsExcitationAtBaseline) {
  configure_arm_start();
  ticks(3);
  field_.values[kY0] = 111.0;  // above 110
  tick();                      // row 3 is written, then the reading suspends
  const std::uint32_t row = engine_.row();
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(engine_.suspend_reasons(), kReasonLimit);
  tick();
  EXPECT_EQ(last_.setpoint[0], 40.0);  // ramp 0 → baseline (max move 10 allows the jump)
  EXPECT_EQ(last_.setpoint[1], 5.0);
  EXPECT_EQ(engine_.row(), row);  // the table does not advance
  EXPECT_NE(engine_.flags() & runlog::kSuspended, 0U);
}

TEST_F(EngineTest, ResumesOnlyAfterDwellInsideTheHysteresisBand) {
  configure_arm_start();  // limits [90, 110], hysteresis 2, dwell 3
  ticks(2);
  field_.values[kY0] = 111.0;
  tick();
  ASSERT_EQ(engine_.state(), State::suspended);
  field_.values[kY0] = 109.0;  // inside the limits but not the band [92, 108]
  ticks(10);
  EXPECT_EQ(engine_.state(), State::suspended);
  field_.values[kY0] = 107.0;  // inside the band
  ticks(2);
  EXPECT_EQ(engine_.state(), State::suspended);  // dwell 3 not yet over
  tick();
  EXPECT_EQ(engine_.suspend_reasons(), 0);
  tick();
  EXPECT_EQ(engine_.state(), State::running);
}

TEST_F(EngineTest, ResumeContinuesWithTheNextTableRow) {
  configure_arm_start();
  ticks(3);  // rows 0, 1, 2
  field_.values[kY0] = 80.0;
  tick();  // row 3 written, then suspended
  field_.values[kY0] = 100.0;
  ticks(3);
  tick();
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_EQ(engine_.row(), 4U);
}

TEST_F(EngineTest, DwellRestartsWhenTheValueLeavesTheBandAgain) {
  configure_arm_start();
  tick();
  field_.values[kY0] = 111.0;
  tick();
  field_.values[kY0] = 100.0;
  ticks(2);
  field_.values[kY0] = 108.5;  // out of the band, inside the limits
  tick();
  field_.values[kY0] = 100.0;
  ticks(2);
  EXPECT_EQ(engine_.suspend_reasons(), kReasonLimit);
  tick();
  EXPECT_EQ(engine_.suspend_reasons(), 0);
}

TEST_F(EngineTest, AbortsWhenSuspendedLongerThanTheTimeout) {
  configure_arm_start();  // timeout 20 ticks
  tick();
  field_.values[kY0] = 200.0;
  tick();  // suspended here; the timeout counts from the next tick
  ticks(19);
  EXPECT_EQ(engine_.state(), State::suspended);
  tick();
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_on_timeout);
  ticks(3);
  EXPECT_EQ(engine_.state(), State::safe);
}

TEST_F(EngineTest, NaNValueCountsAsOutside) {
  configure_arm_start();
  tick();
  field_.values[kY0] = std::numeric_limits<double>::quiet_NaN();
  tick();
  EXPECT_EQ(engine_.state(), State::suspended);
}

TEST_F(EngineTest, FailedExchangesInARowAreCommLoss) {
  configure_arm_start();  // comm_fail_limit 2
  ticks(2);
  field_.ok = false;
  tick();
  EXPECT_EQ(engine_.state(), State::running);  // one failure is tolerated
  EXPECT_NE(engine_.flags() & runlog::kCommLost, 0U);
  tick();
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(engine_.suspend_reasons(), kReasonComm);
  EXPECT_EQ(engine_.comm_losses(), 1U);
}

TEST_F(EngineTest, CommLossWithHoldKeepsTheLastSetpoints) {
  configure_arm_start();
  ticks(3);
  field_.ok = false;
  ticks(2);  // the second failure is the comm loss
  ASSERT_EQ(engine_.state(), State::suspended);
  const double held = last_.setpoint[0];
  EXPECT_NE(held, 40.0);
  ticks(5);
  EXPECT_EQ(last_.setpoint[0], held);
}

TEST_F(EngineTest, CommLossWithRampReturnsToBaseline) {
  EngineConfig c = small_config();
  c.comm_loss = CommLossAction::ramp_to_baseline;
  c.ramp_ticks = 2;
  configure_arm_start(c);
  ticks(3);
  field_.ok = false;
  ticks(5);
  EXPECT_EQ(last_.setpoint[0], 40.0);
  EXPECT_EQ(last_.setpoint[1], 5.0);
}

TEST_F(EngineTest, ReconnectResumesAfterDwellAndAFailureBelowTheLimitDoesNot) {
  configure_arm_start();
  ticks(2);
  field_.ok = false;
  ticks(2);
  ASSERT_EQ(engine_.state(), State::suspended);
  field_.ok = true;
  ticks(2);
  EXPECT_EQ(engine_.state(), State::suspended);
  tick();
  tick();
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_EQ(engine_.failed_exchanges(), 2U);
}

TEST_F(EngineTest, StaleHeartbeatEchoIsCommLoss) {
  configure_arm_start();  // max lag 2 ticks
  ticks(4);
  field_.echo = false;  // the peer stops echoing
  ticks(2);
  EXPECT_EQ(engine_.state(), State::running);
  tick();  // lag 3 > 2
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_NE(engine_.flags() & runlog::kStale, 0U);
  field_.echo = true;
  ticks(4);
  EXPECT_EQ(engine_.state(), State::running);
}

TEST_F(EngineTest, OperatorSuspendWaitsForResumeAndNeverTimesOut) {
  configure_arm_start();
  ticks(2);
  engine_.command(Command::suspend);
  ticks(50);  // longer than the 20-tick timeout
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(engine_.suspend_reasons(), kReasonOperator);
  engine_.command(Command::resume);
  tick();
  EXPECT_EQ(engine_.state(), State::running);
}

TEST_F(EngineTest, ResumeDoesNotOverrideALimitExcursion) {
  configure_arm_start();
  tick();
  field_.values[kY0] = 111.0;
  tick();
  engine_.command(Command::resume);
  tick();
  EXPECT_EQ(engine_.state(), State::suspended);
}

TEST_F(EngineTest, CommandRegisterActsOnAChangeOfValue) {
  configure();
  field_.values[kCommand] = 1.0;  // a "start" left over from before the arm
  arm();
  tick();
  EXPECT_EQ(engine_.state(), State::armed);  // not a change: ignored
  field_.values[kCommand] = 0.0;
  tick();
  field_.values[kCommand] = 1.0;
  tick();  // read here, applied at the next compute
  tick();
  EXPECT_EQ(engine_.state(), State::running);
  field_.values[kCommand] = 2.0;
  ticks(2);
  EXPECT_EQ(engine_.state(), State::suspended);
  field_.values[kCommand] = 3.0;
  ticks(2);
  EXPECT_EQ(engine_.state(), State::running);
  field_.values[kCommand] = 4.0;
  ticks(2);
  EXPECT_TRUE(engine_.state() == State::returning || engine_.state() == State::safe ||
              engine_.state() == State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_by_operator);
}

// Issue 39 §3: acknowledged, the register is cleared after each code the engine reads (the
// Runner writes 0 when command_clear_due(), then calls command_cleared()), so the same code
// written again is a new command. Without the acknowledgement, the second 2 is not seen.
TEST_F(EngineTest, AnAcknowledgedCommandRegisterSeesTheSameCodeTwice) {
  EngineConfig c = small_config();
  c.acknowledge_command = true;
  configure(c);
  field_.values[kCommand] = 1.0;  // left over from before the arm: not acted on, but cleared
  arm();
  EXPECT_TRUE(engine_.command_clear_due());
  field_.values[kCommand] = 0.0;  // what the Runner's write leaves
  engine_.command_cleared();
  EXPECT_FALSE(engine_.command_clear_due());
  tick();
  EXPECT_EQ(engine_.state(), State::armed);
  EXPECT_FALSE(engine_.command_clear_due());  // 0 read: nothing to clear
  engine_.command(Command::start);
  ticks(2);
  ASSERT_EQ(engine_.state(), State::running);
  for (int round = 0; round < 2; ++round) {  // suspend by the register twice, the same code
    field_.values[kCommand] = 2.0;
    tick();  // read here
    ASSERT_TRUE(engine_.command_clear_due()) << round;
    field_.values[kCommand] = 0.0;
    engine_.command_cleared();
    tick();  // applied at this compute
    EXPECT_EQ(engine_.state(), State::suspended) << round;
    engine_.command(Command::resume);
    ticks(2);
    EXPECT_EQ(engine_.state(), State::running) << round;
  }
  EXPECT_EQ(engine_.commands_acknowledged(), 3U);  // the leftover and the two suspends
}

TEST_F(EngineTest, AnUnacknowledgedCommandRegisterMissesTheSameCodeTwice) {
  configure_arm_start();
  ticks(2);
  field_.values[kCommand] = 2.0;
  ticks(2);
  ASSERT_EQ(engine_.state(), State::suspended);
  EXPECT_FALSE(engine_.command_clear_due());
  engine_.command(Command::resume);
  ticks(2);
  ASSERT_EQ(engine_.state(), State::running);
  ticks(2);  // the register still holds 2: the same value, not a new command
  EXPECT_EQ(engine_.state(), State::running);
}

}  // namespace excite::engine::testing
