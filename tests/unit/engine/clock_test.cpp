// SPDX-License-Identifier: MIT
// Time is counted on the clock, not in ticks executed (issue 10 item 3): ticks the loop
// skipped (overruns) move the log's k, are flagged, and count towards the suspension
// timeout and the unconfirmed window; the table, ramp and max_move advance per write.
#include "engine_fixture.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine::testing {

TEST_F(EngineTest, SuspensionTimeoutCountsSkippedTicks) {
  configure_arm_start();  // timeout 20 ticks, comm loss after 2 failed exchanges
  tick();
  field_.ok = false;  // the peer stops answering: each exchange now takes long
  tick();
  tick();
  ASSERT_EQ(engine_.state(), State::suspended);
  tick(9);  // 10 ticks of the clock: 10 of 20
  EXPECT_EQ(engine_.state(), State::suspended);
  tick(9);  // 20 of 20
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_on_timeout);
  // Counted in executed ticks this would have taken 20 ticks of (here) ten times the period.
  EXPECT_EQ(engine_.skipped_ticks(), 18U);
}

TEST_F(EngineTest, SkippedTicksMoveTheLogIndexAndFlagOnlyTheirRow) {
  configure_arm_start();
  tick();
  tick();
  EXPECT_EQ(engine_.record(0).tick, 1U);
  tick(5);  // grid points 2…6 were missed: this is tick 7
  const TickRecord r = engine_.record(0);
  EXPECT_EQ(r.tick, 7U);
  EXPECT_NE(r.flags & runlog::kSkipped, 0U);
  EXPECT_EQ(r.row, 2U);  // the table advances per tick written, not per grid point
  EXPECT_EQ(last_.setpoint[0], 40.0 + 3.0);
  tick();
  EXPECT_EQ(engine_.record(0).tick, 8U);
  EXPECT_EQ(engine_.record(0).flags & runlog::kSkipped, 0U);
  EXPECT_EQ(engine_.skipped_ticks(), 5U);
  EXPECT_EQ(engine_.rows_flagged(runlog::kSkipped), 1U);
  EXPECT_EQ(engine_.ticks(), 9U);
}

TEST_F(EngineTest, ReadbacksAndHeartbeatFollowTheWritesAcrossSkippedTicks) {
  EngineConfig c = small_config();
  c.verify_readbacks = true;
  c.readback_lag_ticks = 1;
  c.readback_mismatch_limit = 0;  // one mismatch is a fault
  configure_arm_start(c);
  for (int k = 0; k < 6; ++k) tick(k % 2 == 0 ? 40 : 0);  // skips beyond the lag ring (16)
  EXPECT_FALSE(engine_.readback_fault().valid);
  EXPECT_EQ(engine_.readback_mismatches(), 0U);
  EXPECT_EQ(engine_.flags() & runlog::kStale, 0U);  // the echo is one write behind, not 40
  EXPECT_EQ(engine_.state(), State::running);
}

TEST_F(EngineTest, UnconfirmedWindowCountsSkippedTicks) {
  EngineConfig c = small_config();
  c.ramp_ticks = 2;
  configure_arm_start(c);  // timeout 20
  tick();
  engine_.command(Command::abort);
  tick();  // aborted
  field_.ok = false;
  tick();
  tick();  // returning, comm lost
  ASSERT_EQ(engine_.state(), State::returning);
  tick(30);  // ramp 2 + timeout 20 = 22 ticks of the clock have passed
  EXPECT_EQ(engine_.state(), State::safe_unconfirmed);
}

// Issue 10 item 6: a peer that restarted echoes a heartbeat from before the run (0), not one
// the gateway sent since the last good exchange: that row starts a new segment.
TEST_F(EngineTest, RestartedPeerIsFlaggedAsADiscontinuity) {
  configure_arm_start();
  ticks(5);  // echoes 1…5 seen
  field_.ok = false;
  tick();  // heartbeat 6 lost on the way
  field_.ok = true;
  engine_.compute();           // heartbeat 7, not yet written
  field_.values[kEcho] = 0.0;  // the restarted peer: its echo register starts at 0
  engine_.check_peer_continuity(field_.values);
  EXPECT_NE(engine_.flags() & runlog::kDiscontinuity, 0U);
  engine_.observe(true, field_.values);
  EXPECT_NE(engine_.record(0).flags & runlog::kDiscontinuity, 0U);
  EXPECT_EQ(engine_.discontinuities(), 1U);
  EXPECT_EQ(engine_.rows_flagged(runlog::kDiscontinuity), 1U);
}

TEST_F(EngineTest, PeerThatGotTheWritesOfTheOutageIsContinuous) {
  // Echo 5: the last one seen; 6, 7: writes of the outage that arrived, their replies lost;
  // 9: ahead of anything sent (the tick's own heartbeat 8 is not written yet).
  for (const double echo : {5.0, 6.0, 7.0, 9.0}) {
    field_ = Field{};
    configure_arm_start();
    ticks(5);  // echoes 1…5 seen
    field_.ok = false;
    ticks(2);  // heartbeats 6, 7
    field_.ok = true;
    engine_.compute();  // heartbeat 8
    field_.values[kEcho] = echo;
    engine_.check_peer_continuity(field_.values);
    const bool flagged = (engine_.flags() & runlog::kDiscontinuity) != 0;
    EXPECT_EQ(flagged, echo > 8.0) << echo;
  }
}

}  // namespace excite::engine::testing
