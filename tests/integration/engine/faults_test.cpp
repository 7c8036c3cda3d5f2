// SPDX-License-Identifier: MIT
// Engine + simlink plant: every state and fault path in a closed loop, on virtual time.
#include <algorithm>
#include <fstream>

#include "firmware/runlog/format.hpp"
#include "gateway_fixture.hpp"

namespace excite::testing {

namespace {
std::size_t count_flag(const runlog::RunLog& log, std::uint32_t flag) {
  return static_cast<std::size_t>(std::count_if(
      log.flags.begin(), log.flags.end(), [flag](std::uint32_t f) { return (f & flag) != 0; }));
}
}  // namespace

TEST_F(GatewayLoop, ExcursionSuspendsThenResumesAfterDwellAndStillCompletes) {
  // GIVEN a disturbance that pushes xD beyond its test limit from tick 100 to tick 150
  script_.at(100, [this] { bus_->set_disturbance(0, 2.0 * kTestBand); });
  script_.at(150, [this] { bus_->set_disturbance(0, 0.0); });
  // WHEN the plan is streamed
  const app::RunStats stats = run();
  // THEN the run is suspended during the excursion, resumes after the dwell and completes
  EXPECT_EQ(stats.outcome, engine::Outcome::completed);
  EXPECT_EQ(engine().suspensions(), 1U);
  const runlog::RunLog log = read_log();
  const std::size_t suspended = count_flag(log, runlog::kSuspended);
  EXPECT_GE(suspended, 50U + 10U - 2U);  // the excursion plus the 10-tick dwell
  EXPECT_LE(suspended, 50U + 10U + 2U);
  EXPECT_EQ(log.rows(), stats.ticks);
  EXPECT_EQ(engine().row(), table_.samples - 1);  // every row was streamed, none skipped
  EXPECT_GT(stats.ticks, table_.samples + suspended);
}

TEST_F(GatewayLoop, ExcitationIsAtBaselineWhileSuspended) {
  script_.at(200, [this] { bus_->set_disturbance(1, -2.0 * kTestBand); });
  script_.at(300, [this] { bus_->set_disturbance(1, 0.0); });
  run();
  const runlog::RunLog log = read_log();
  std::size_t at_baseline = 0;
  for (std::size_t r = 0; r < log.rows(); ++r) {
    if ((log.flags[r] & runlog::kSuspended) == 0 || r < 215) continue;  // past the ramp-out
    for (std::uint32_t c = 0; c < kInputs; ++c) EXPECT_EQ(log.du[c][r], 0.0) << "row " << r;
    ++at_baseline;
  }
  EXPECT_GT(at_baseline, 50U);
}

TEST_F(GatewayLoop, PersistentExcursionAbortsOnTimeoutAndReturnsToBaseline) {
  script_.at(100, [this] { bus_->set_disturbance(2, 2.0 * kTestBand); });
  const app::RunStats stats = run();
  EXPECT_EQ(stats.outcome, engine::Outcome::aborted_on_timeout);
  EXPECT_EQ(stats.final_state, engine::State::safe);
  for (std::uint32_t i = 0; i < kInputs; ++i) EXPECT_EQ(bus_->held_setpoint(i), kU0[i]);
  EXPECT_LT(stats.ticks, 100U + 200U + 20U);
  EXPECT_EQ(read_log().rows(), stats.ticks);
}

TEST_F(GatewayLoop, CommLossHoldsReconnectsAndMarksTheLog) {
  script_.at(300, [this] { bus_->drop(8, hal::StatusCode::link_lost); });
  const app::RunStats stats = run();
  EXPECT_EQ(stats.outcome, engine::Outcome::completed);
  EXPECT_EQ(bus_->dropped(), 8U);
  EXPECT_EQ(engine().comm_losses(), 1U);
  const runlog::RunLog log = read_log();
  EXPECT_EQ(log.rows(), stats.ticks);
  // The failed exchanges and the dwell after the reconnect are marked comm_lost.
  EXPECT_GE(count_flag(log, runlog::kCommLost), 8U + 10U - 1U);
  // Hold: the setpoints logged during the loss do not move.
  // Ticks 301…308 fail; the loss is declared at the third failure (303), whose row is the
  // last excitation; it is held until the dwell after the reconnect is over.
  const std::size_t first = 303;
  for (std::size_t r = first; r < 315; ++r) {
    for (std::uint32_t c = 0; c < kInputs; ++c) EXPECT_EQ(log.u[c][r], log.u[c][first]);
  }
  // dy repeats the last good value while the link is down.
  EXPECT_EQ(log.dy[0][303], log.dy[0][300]);
}

TEST_F(GatewayLoop, StaleHeartbeatEchoWithRampActionRampsThePlantToBaseline) {
  config_.comm_loss = engine::CommLossAction::ramp_to_baseline;
  script_.at(400, [this] { bus_->freeze_echo(true); });
  script_.at(440, [this] {
    for (std::uint32_t i = 0; i < kInputs; ++i) held_[i] = bus_->held_setpoint(i);
    bus_->freeze_echo(false);
  });
  const app::RunStats stats = run();
  EXPECT_EQ(stats.outcome, engine::Outcome::completed);
  for (std::uint32_t i = 0; i < kInputs; ++i) EXPECT_EQ(held_[i], kU0[i]) << "input " << i;
  const runlog::RunLog log = read_log();
  EXPECT_GT(count_flag(log, runlog::kStale), 30U);
}

TEST_F(GatewayLoop, CommLossBeyondTheTimeoutAborts) {
  script_.at(50, [this] { bus_->drop(1000000); });
  const app::RunStats stats = run();
  EXPECT_EQ(stats.outcome, engine::Outcome::aborted_on_timeout);
  // the link never came back: the baseline was written but never read back
  EXPECT_EQ(stats.final_state, engine::State::safe_unconfirmed);
  EXPECT_EQ(read_log().rows(), stats.ticks);
}

TEST_F(GatewayLoop, OperatorCommandsThroughTheCommandRegister) {
  script_.at(5, [this] { bus_->set_command(1.0); });    // start
  script_.at(100, [this] { bus_->set_command(2.0); });  // suspend
  script_.at(400, [this] { bus_->set_command(3.0); });  // resume
  script_.at(700, [this] { bus_->set_command(4.0); });  // abort
  const app::RunStats stats = run(engine::Command::none);
  EXPECT_EQ(stats.outcome, engine::Outcome::aborted_by_operator);
  EXPECT_EQ(stats.final_state, engine::State::safe);
  EXPECT_EQ(script_.states[6], engine::State::armed);
  EXPECT_EQ(script_.states[8], engine::State::running);
  EXPECT_EQ(script_.states[300], engine::State::suspended);  // operator: no timeout
  EXPECT_EQ(script_.states[500], engine::State::running);
  EXPECT_LT(stats.ticks, 720U);
}

TEST_F(GatewayLoop, OperatorCommandsThroughTheMailbox) {
  script_.at(50, [this] { commands_.post(engine::Command::suspend); });
  script_.at(60, [this] { commands_.post(engine::Command::resume); });
  script_.at(90, [this] { commands_.post(engine::Command::abort); });
  const app::RunStats stats = run();
  EXPECT_EQ(script_.states[55], engine::State::suspended);
  EXPECT_EQ(script_.states[70], engine::State::running);
  EXPECT_EQ(stats.outcome, engine::Outcome::aborted_by_operator);
  EXPECT_EQ(read_log().rows(), stats.ticks);
}

TEST_F(GatewayLoop, SlowWriterWithAnAdequateRingLosesNothing) {
  row_delay_ = std::chrono::microseconds(50);  // ~0.2 s for the run
  const app::RunStats stats = run();
  EXPECT_EQ(stats.ring_overruns, 0U);
  EXPECT_EQ(rows_written_, stats.ticks);
  EXPECT_EQ(read_log().rows(), stats.ticks);
}

TEST_F(GatewayLoop, RingOverrunIsCountedNeverSilent) {
  // A writer far slower than the virtual-time loop: the 256-record ring must overflow.
  ring_records_ = 256;
  row_delay_ = std::chrono::milliseconds(1);
  max_ticks_ = 3000;
  config_.suspend_timeout_s = 0.0;
  script_.at(0, [this] { bus_->set_disturbance(0, 2.0 * kTestBand); });  // stay suspended
  const app::RunStats stats = run();
  EXPECT_EQ(stats.ticks, 3000U);
  EXPECT_GT(stats.ring_overruns, 0U);
  EXPECT_EQ(rows_written_ + stats.ring_overruns, stats.ticks);
  // The file holds exactly the rows written; the loss is in the counters (and the
  // gateway's exit code 8), never silent.
  std::ifstream in(log_path_);
  std::string line;
  std::uint64_t data_rows = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#' && line.rfind("t_min", 0) != 0) ++data_rows;
  }
  EXPECT_EQ(data_rows, rows_written_);
}

}  // namespace excite::testing
