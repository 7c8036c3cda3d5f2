// SPDX-License-Identifier: MIT
// Plan segments: a staged, approved table is taken at a period boundary of the running table
// (or its end), row 0 first, the baseline unchanged and max_move still limiting every move;
// without approval it is never taken; a refused segment leaves the running table untouched.
#include <cmath>
#include <string>

#include "engine_fixture.hpp"
#include "firmware/engine/segment.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine::testing {

class SegmentTest : public EngineTest {
 protected:
  // The next segment: channel 0 = +10, +20, …; channel 1 = +1, +2, …
  void SetUp() override {
    EngineTest::SetUp();
    for (std::uint32_t k = 0; k < kRows; ++k) {
      next_[2 * k] = 10.0 * (k + 1.0);
      next_[2 * k + 1] = k + 1.0;
    }
  }
  signal::ConstTableView next() const { return {next_.data(), 2, kRows}; }
  std::array<double, 2 * kRows> next_{};
};

TEST_F(SegmentTest, AnApprovedSegmentIsTakenAtTheEndOfTheRunningTableRowZeroFirst) {
  EngineConfig c = small_config();
  c.input[0].max_move = 100.0;
  c.input[1].max_move = 100.0;
  configure_arm_start(c);
  ticks(2);
  ASSERT_TRUE(engine_.stage(next(), true));
  for (std::uint32_t k = 2; k < kRows; ++k) {
    tick();
    EXPECT_EQ(engine_.segment(), 0U);
    EXPECT_EQ(engine_.row(), k);
  }
  tick();  // the row after the last: row 0 of the next segment
  EXPECT_EQ(engine_.segment(), 1U);
  EXPECT_EQ(engine_.row(), 0U);
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_DOUBLE_EQ(last_.setpoint[0], 40.0 + 10.0);  // baseline unchanged
  EXPECT_DOUBLE_EQ(last_.setpoint[1], 5.0 + 1.0);
  EXPECT_EQ(engine_.record(0).segment, 1U);
  EXPECT_FALSE(engine_.segment_staged());
  ticks(static_cast<int>(kRows) - 1);
  EXPECT_EQ(engine_.row(), kRows - 1);
  tick();
  EXPECT_EQ(engine_.state(), State::completed);  // the new segment ran to its end
}

TEST_F(SegmentTest, ASwitchHappensAtAPeriodBoundaryOfTheRunningTable) {
  EngineConfig c = small_config();
  c.input[0].max_move = 100.0;
  c.input[1].max_move = 100.0;
  c.segment_period_rows = 3;  // boundaries before rows 3 and 6
  configure_arm_start(c);
  tick();  // row 0
  ASSERT_TRUE(engine_.stage(next(), true));
  tick();  // row 1
  tick();  // row 2
  EXPECT_EQ(engine_.segment(), 0U);
  tick();  // would be row 3: a boundary
  EXPECT_EQ(engine_.segment(), 1U);
  EXPECT_EQ(engine_.row(), 0U);
  EXPECT_DOUBLE_EQ(last_.setpoint[0], 50.0);
}

TEST_F(SegmentTest, AnUnapprovedSegmentIsNeverTaken) {
  configure_arm_start();
  ASSERT_TRUE(engine_.stage(next(), false));
  tick();
  for (int i = 0; i < 12 && engine_.state() == State::running; ++i) {
    tick();
    EXPECT_EQ(engine_.segment(), 0U);
  }
  EXPECT_EQ(engine_.outcome(), Outcome::completed);
  EXPECT_EQ(engine_.segment(), 0U);
}

TEST_F(SegmentTest, ApproveAfterStagingTakesItAndApproveBeforeStagingDoesNot) {
  EngineConfig c = small_config();
  c.input[0].max_move = 100.0;
  c.input[1].max_move = 100.0;
  configure_arm_start(c);
  tick();                             // row 0
  engine_.command(Command::approve);  // nothing staged: approves nothing
  tick();
  ASSERT_TRUE(engine_.stage(next(), false));
  EXPECT_FALSE(engine_.segment_approved());
  engine_.command(Command::approve);
  tick();
  EXPECT_TRUE(engine_.segment_approved());
  ticks(static_cast<int>(kRows) - 2);
  EXPECT_EQ(engine_.segment(), 1U);
}

TEST_F(SegmentTest, TheCommandRegisterApprovesWithCodeFive) {
  EXPECT_EQ(command_from_code(5), Command::approve);
  EXPECT_STREQ(to_string(Command::approve), "approve");
}

TEST_F(SegmentTest, NoMoveAtTheSwitchExceedsMaxMove) {
  // GIVEN the running table ends at +8 / −8 and the next starts at +10 / +1 from the
  // baseline (a jump of 9 on channel 1), with max_move 2
  EngineConfig c = small_config();
  c.input[0].max_move = 2.0;
  c.input[1].max_move = 2.0;
  configure_arm_start(c);
  ASSERT_TRUE(engine_.stage(next(), true));
  // WHEN the run streams through the switch and the next segment
  double previous0 = 40.0;
  double previous1 = 5.0;
  bool limited_after_switch = false;
  for (int i = 0; i < 2 * static_cast<int>(kRows) + 2; ++i) {
    const TickOutput& out = tick();
    // THEN no move exceeds max_move, and the jump at the switch is rate-limited
    EXPECT_LE(std::abs(out.setpoint[0] - previous0), 2.0 + 1e-12) << "tick " << i;
    EXPECT_LE(std::abs(out.setpoint[1] - previous1), 2.0 + 1e-12) << "tick " << i;
    if (engine_.segment() == 1 && engine_.row() == 0) {
      limited_after_switch = (engine_.flags() & runlog::kRateLimited) != 0;
    }
    previous0 = out.setpoint[0];
    previous1 = out.setpoint[1];
  }
  EXPECT_EQ(engine_.segment(), 1U);
  EXPECT_TRUE(limited_after_switch);
}

TEST_F(SegmentTest, ARefusedStageLeavesTheRunningTableUntouched) {
  configure_arm_start();
  tick();
  const std::array<double, 3 * kRows> three{};
  const Status s = engine_.stage({three.data(), 3, kRows}, true);
  EXPECT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("segment table = 3 channels x 8 samples, expected 2"),
            std::string::npos)
      << s.message();
  EXPECT_FALSE(engine_.segment_staged());
  for (std::uint32_t k = 1; k < kRows; ++k) {
    tick();
    EXPECT_DOUBLE_EQ(last_.setpoint[0], 40.0 + (k + 1.0));
  }
  tick();
  EXPECT_EQ(engine_.state(), State::completed);
  EXPECT_EQ(engine_.segment(), 0U);
}

TEST_F(SegmentTest, ASecondStageWhileOneWaitsIsRefused) {
  configure_arm_start();
  ASSERT_TRUE(engine_.stage(next(), false));
  const Status s = engine_.stage(next(), false);
  EXPECT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("expected none waiting"), std::string::npos);
}

// Awaiting the next segment (segment_await_ticks): at the table's end the baseline is held,
// each row flagged suspended in state running, until a segment is approved or the wait ends.
TEST_F(SegmentTest, AtTheTablesEndTheBaselineIsHeldUntilASegmentIsApproved) {
  EngineConfig c = small_config();
  c.input[0].max_move = 100.0;
  c.input[1].max_move = 100.0;
  c.segment_await_ticks = 50;
  configure_arm_start(c);
  ticks(static_cast<int>(kRows) - 1);
  EXPECT_FALSE(engine_.awaiting_segment());  // the last row is not written yet
  tick();
  EXPECT_EQ(engine_.row(), kRows - 1);
  EXPECT_TRUE(engine_.awaiting_segment());  // a lock-step loop stops ticking here
  for (int i = 0; i < 5; ++i) {
    tick();
    EXPECT_EQ(engine_.state(), State::running);
    EXPECT_NE(engine_.flags() & runlog::kSuspended, 0U);
    EXPECT_DOUBLE_EQ(last_.setpoint[0], 40.0);  // the baseline
    EXPECT_DOUBLE_EQ(last_.setpoint[1], 5.0);
    EXPECT_EQ(engine_.record(0).segment, 0U);
  }
  EXPECT_EQ(engine_.awaited_ticks(), 5U);
  ASSERT_TRUE(engine_.stage(next(), false));
  EXPECT_TRUE(engine_.awaiting_segment());  // staged, not approved
  engine_.command(Command::approve);
  EXPECT_FALSE(engine_.awaiting_segment());  // an approve pending counts
  tick();
  EXPECT_EQ(engine_.segment(), 1U);
  EXPECT_EQ(engine_.row(), 0U);
  EXPECT_EQ(engine_.flags() & runlog::kSuspended, 0U);
  EXPECT_DOUBLE_EQ(last_.setpoint[0], 50.0);
  ticks(static_cast<int>(kRows) - 1);
  EXPECT_TRUE(engine_.awaiting_segment());  // the new table's end awaits again
}

TEST_F(SegmentTest, TheWaitEndsAfterItsTicksOrEndAwaitAndTheRunCompletes) {
  EngineConfig c = small_config();
  c.segment_await_ticks = 3;
  configure_arm_start(c);
  ticks(static_cast<int>(kRows));
  ticks(3);  // three rows holding the baseline
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_EQ(engine_.awaited_ticks(), 3U);
  tick();
  EXPECT_EQ(engine_.state(), State::completed);
  EXPECT_EQ(engine_.outcome(), Outcome::completed);

  // Timed by the loop (lock-step): end_await() and the next tick completes, no row held.
  field_ = Field{};
  configure_arm_start(c);  // a fresh run
  ticks(static_cast<int>(kRows));
  EXPECT_TRUE(engine_.awaiting_segment());
  engine_.end_await();
  EXPECT_FALSE(engine_.awaiting_segment());
  tick();
  EXPECT_EQ(engine_.state(), State::completed);
  EXPECT_EQ(engine_.awaited_ticks(), 0U);
}

TEST_F(SegmentTest, AnAbortOrSuspendPendingEndsTheWaitWithoutASegment) {
  EngineConfig c = small_config();
  c.segment_await_ticks = 100;
  configure_arm_start(c);
  ticks(static_cast<int>(kRows));
  EXPECT_TRUE(engine_.awaiting_segment());
  engine_.command(Command::approve);  // nothing staged: still awaiting
  EXPECT_TRUE(engine_.awaiting_segment());
  engine_.command(Command::abort);
  EXPECT_FALSE(engine_.awaiting_segment());
  tick();
  EXPECT_EQ(engine_.state(), State::aborted);
}

TEST(SegmentCheck, ChannelsLimitsAndSampleTimeMustBeTheRunningPlans) {
  plan::Plan running;
  running.recipe.channels = 2;
  running.meta.sample_time_min = 1.0;
  ASSERT_TRUE(plan::set_text(running.meta.channels[0].name, "L"));
  ASSERT_TRUE(plan::set_text(running.meta.channels[1].name, "V"));
  running.meta.channels[0].min = -1.0;
  running.meta.channels[0].max = 1.0;
  running.meta.channels[1].min = -2.0;
  running.meta.channels[1].max = 2.0;
  EXPECT_TRUE(check_segment(running, running));

  plan::Plan next = running;
  next.recipe.channels = 3;
  EXPECT_STREQ(check_segment(running, next).message(),
               "segment.channels = 3, expected 2 (the running plan's)");
  next = running;
  next.meta.sample_time_min = 2.0;
  EXPECT_STREQ(check_segment(running, next).message(),
               "segment.sample_time_min = 2, expected 1 (the running plan's)");
  next = running;
  next.meta.channels[1].max = 3.0;
  EXPECT_STREQ(check_segment(running, next).message(),
               "segment.channels[1].max = 3, expected 2 (the running plan's)");
  next = running;
  ASSERT_TRUE(plan::set_text(next.meta.channels[0].name, "R"));
  EXPECT_STREQ(check_segment(running, next).message(),
               "segment.channels[0].name = \"R\", expected \"L\" (the running plan's)");
}

TEST(SegmentCheck, BaselinePlusTheSegmentTableMustStayWithinTheLimits) {
  EngineConfig c = small_config();
  const std::array<double, 2> baseline{40.0, 5.0};
  std::array<double, 4> table{1.0, -1.0, 70.0, -2.0};  // 40 + 70 = 110 > 100
  const Status s = check_segment_table(c, baseline, {table.data(), 2, 2});
  EXPECT_FALSE(s);
  EXPECT_STREQ(s.message(),
               "input[0] baseline + segment table = [40, 110], expected within [0, 100] "
               "(baseline 40)");
  table[2] = 50.0;
  EXPECT_TRUE(check_segment_table(c, baseline, {table.data(), 2, 2}));
}

}  // namespace excite::engine::testing
