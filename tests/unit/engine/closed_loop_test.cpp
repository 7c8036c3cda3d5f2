// SPDX-License-Identifier: MIT
// The engine in closed loop (issue 42 §2): the setpoints are test offsets written to a
// running controller; its mode and MV statuses are watched (a clamped or wound-up MV, or the
// controller out of its mode, suspends the test and after controller.timeout_ticks aborts
// it), its moves, applied MVs and setpoints in force are data for the log, and safe needs
// the offsets read back at zero and held with the controller in its mode.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "closed_loop_fixture.hpp"

namespace excite::engine::testing {

TEST_F(ClosedLoopTest, TheControllersDataIsRecordedAndTheAppliedMvIsNoFault) {
  start();
  ticks(3);
  // The controller moves against the offset and the plant got something else than the
  // offset: data, not a verified-write fault (only the offset registers are verified).
  field_.values[kMove0] = -0.25;
  field_.values[kApplied0] = last_.setpoint[0] - 0.25;
  field_.values[kSetpointInForce] = 0.125;
  field_.values[kStatus1] = 0.0;
  tick();
  const TickRecord r = engine_.record(0);
  EXPECT_TRUE(r.closed_loop);
  EXPECT_EQ(r.mvs, 2U);
  EXPECT_EQ(r.cvs, 1U);
  EXPECT_EQ(r.r[0], r.du[0]) << "r: the offset written";
  EXPECT_EQ(r.r[0], 4.0) << "row 3 of the table, ramp 0, baseline 0";
  EXPECT_EQ(r.uc[0], -0.25);
  EXPECT_EQ(r.du_applied[0], 2.75) << "as read: the offset of the tick before, less 0.25";
  EXPECT_EQ(r.ysp[0], 0.125);
  EXPECT_EQ(r.mode, 1);
  EXPECT_EQ(r.st[0], 0);
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_EQ(engine_.readback_mismatches(), 0U);
}

TEST_F(ClosedLoopTest, AnOpenLoopRecordHasNoClosedLoopFields) {
  EngineConfig c = closed_config();
  c.controller = {};
  c.controller.mode = kNone;
  start(c);
  tick();
  EXPECT_FALSE(engine_.record(0).closed_loop);
}

TEST_F(ClosedLoopTest, AClampedMvSuspendsTheTestUntilItIsFreeAgain) {
  start();
  ticks(2);
  ASSERT_EQ(engine_.state(), State::running);
  field_.values[kStatus1] = 2.0;  // clamped high
  tick();
  EXPECT_NE(engine_.suspend_reasons() & kReasonController, 0);
  tick();
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(last_.setpoint[0], 0.0) << "suspended: the offsets ramp back to zero";
  field_.values[kStatus1] = 0.0;
  ticks(3);  // resume_dwell_ticks = 3
  tick();
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_EQ(engine_.mv_limited_episodes(), 1U);
  EXPECT_EQ(engine_.controller_mode_losses(), 0U);
  field_.values[kStatus0] = 3.0;  // windup: a second episode
  ticks(2);
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(engine_.mv_limited_episodes(), 2U);
}

TEST_F(ClosedLoopTest, ManualSuspendsThenAbortsAfterTheControllerTimeout) {
  start();
  ticks(2);
  field_.values[kMode] = 0.0;  // off: the operator took the loop to manual
  field_.values[kStatus0] = 4.0;
  field_.values[kStatus1] = 4.0;
  ticks(2);
  EXPECT_EQ(engine_.state(), State::suspended);
  EXPECT_EQ(engine_.controller_mode_losses(), 1U);
  ticks(5);  // controller.timeout_ticks = 5
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_on_controller);
  // Returning: the offsets go to zero and read back, but the controller is not in its mode:
  // never safe, only safe_unconfirmed at the confirmation timeout.
  for (int i = 0; i < 40 && !finished(engine_.state()); ++i) tick();
  EXPECT_EQ(engine_.state(), State::safe_unconfirmed);
  EXPECT_EQ(last_.setpoint[0], 0.0);
  EXPECT_EQ(last_.setpoint[1], 0.0);
}

TEST_F(ClosedLoopTest, SafeIsTheOffsetsAtZeroHeldWithTheControllerInItsMode) {
  start();
  for (int i = 0; i < 60 && !finished(engine_.state()); ++i) tick();
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(engine_.outcome(), Outcome::completed);
}

// The controller out of its mode only while the offsets return: not safe until it is back.
TEST_F(ClosedLoopTest, SafeWaitsForTheControllerInItsMode) {
  start();
  for (int i = 0; i < 60 && engine_.state() != State::returning; ++i) tick();
  field_.values[kMode] = 3.0;          // suspended by its operator
  for (int i = 0; i < 5; ++i) tick();  // within confirm_timeout_ticks = 10
  EXPECT_EQ(engine_.state(), State::returning) << "offsets at zero, controller not in mode";
  field_.values[kMode] = 1.0;
  for (int i = 0; i < 8 && !finished(engine_.state()); ++i) tick();
  EXPECT_EQ(engine_.state(), State::safe);
}

TEST(ClosedLoopConfig, BadIndicesAreRefusedByName) {
  EngineConfig c = closed_config();
  c.controller.status[1] = 99;
  const Status s = validate(c);
  EXPECT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("controller.status[1] = 99, expected a value index"),
            std::string::npos)
      << s.message();
  c = closed_config();
  c.controller.mvs = kMaxInputs + 1;
  EXPECT_FALSE(validate(c));
  c = closed_config();
  c.controller.mode = 40;
  EXPECT_NE(std::string(validate(c).message()).find("controller.mode = 40"), std::string::npos);
}

}  // namespace excite::engine::testing
