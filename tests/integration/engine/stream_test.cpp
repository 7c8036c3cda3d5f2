// SPDX-License-Identifier: MIT
// Engine + simlink plant: the whole plan is streamed, every tick is logged, the log reads back.
#include "firmware/runlog/format.hpp"
#include "gateway_fixture.hpp"

namespace excite::testing {

TEST_F(GatewayLoop, StreamsTheWholePlanAndEndsSafeAtBaseline) {
  const app::RunStats stats = run();
  EXPECT_EQ(stats.final_state, engine::State::safe);
  EXPECT_EQ(stats.outcome, engine::Outcome::completed);
  EXPECT_EQ(engine().row(), table_.samples - 1);
  for (std::uint32_t i = 0; i < kInputs; ++i) EXPECT_EQ(bus_->held_setpoint(i), kU0[i]);
  // one exchange per tick, none lost, plus the baseline written and read back at arm
  EXPECT_EQ(bus_->writes(), stats.ticks + 1);
}

TEST_F(GatewayLoop, TicksLoggedEqualTicksExecutedAndTheLogReadsBack) {
  const app::RunStats stats = run();
  EXPECT_EQ(stats.ring_overruns, 0U);
  EXPECT_EQ(rows_written_, stats.ticks);
  const runlog::RunLog log = read_log();
  ASSERT_EQ(log.rows(), stats.ticks);
  EXPECT_EQ(log.k.front(), 0U);
  EXPECT_EQ(log.k.back(), stats.ticks - 1);
  EXPECT_EQ(log.input_names, (std::vector<std::string>{"L", "V", "S", "F"}));
  EXPECT_EQ(log.producer, "excite-gateway (integration test)");
  EXPECT_EQ(log.sample_time_min, 1.0);  // the plan's T, minutes, as the plan file holds it
  EXPECT_EQ(log.t_min[10], 10.0);
}

TEST_F(GatewayLoop, LoggedExcitationIsTheTableOnceRampedIn) {
  for (std::uint32_t c = 0; c < kInputs; ++c) config_.setpoints[c].max_move = 50.0;  // no slew
  const app::RunStats stats = run();
  ASSERT_GT(stats.ticks, table_.samples);
  const runlog::RunLog log = read_log();
  // The start command is taken at tick 0, so tick k writes row k; after the 5-tick ramp
  // and where the slew limit did not act, the logged du equals the table bit for bit.
  std::size_t compared = 0;
  for (std::uint32_t k = 10; k < table_.samples; ++k) {
    for (std::uint32_t c = 0; c < kInputs; ++c) {
      const double logged = log.du[c][k];
      EXPECT_EQ(logged, (kU0[c] + table_.at(k, c)) - kU0[c]) << "row " << k << " channel " << c;
      ++compared;
    }
  }
  EXPECT_EQ(compared, kInputs * (table_.samples - 10U));
}

TEST_F(GatewayLoop, OutputsRespondToTheExcitation) {
  run();
  const runlog::RunLog log = read_log();
  double energy = 0.0;
  for (double v : log.dy[0]) energy += v * v;
  EXPECT_GT(energy, 1.0);  // the plant moved: the closed loop is real
}

TEST_F(GatewayLoop, RampInAndOutAreBumpless) {
  run();
  const runlog::RunLog log = read_log();
  for (std::size_t r = 1; r < log.rows(); ++r) {
    for (std::uint32_t c = 0; c < kInputs; ++c) {
      EXPECT_LE(std::abs(log.u[c][r] - log.u[c][r - 1]), 5.0 + 1e-9) << "row " << r;
    }
  }
  for (std::uint32_t c = 0; c < kInputs; ++c) {
    // The first tick writes row 0 at a fifth of its amplitude (5-tick ramp); the run ends
    // exactly at the baseline.
    EXPECT_NEAR(log.du[c].front(), 0.2 * table_.at(0, c), 1e-12);
    EXPECT_EQ(log.du[c].back(), 0.0);
  }
}

}  // namespace excite::testing
