// SPDX-License-Identifier: MIT
// The distortion prediction (issue 10 item 5) against the engine itself: the rows the
// prediction calls rate-limited or clamped are the rows the engine flags when it streams
// the same table with the same baseline.
#include "firmware/engine/distortion.hpp"

#include "engine_fixture.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine::testing {

TEST_F(EngineTest, PredictedRateLimitedRowsAreTheRowsTheEngineFlags) {
  EngineConfig c = small_config();
  c.input[0].max_move = 1.5;  // channel 0: 0.5 (ramp ½ · 1), then 1.5 (ramp 1 · 2), then +1
  c.input[1].max_move = 0.5;  // channel 1: −0.5, then −1.5, −1, …: rows 1…7 limited
  c.ramp_ticks = 2;
  const Distortion d = predict_distortion(c, table(), {});
  EXPECT_EQ(d.rows, kRows);
  EXPECT_FALSE(d.clamping_known);
  EXPECT_EQ(d.channel[0].rate_limited_rows, 0U);
  EXPECT_EQ(d.channel[1].rate_limited_rows, kRows - 1);
  EXPECT_DOUBLE_EQ(d.fraction(1), 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(d.channel[0].largest_move, 1.5);
  EXPECT_EQ(d.channel[0].largest_move_row, 1U);

  // The engine, streaming the same table, flags the same rows rate-limited.
  configure_arm_start(c);
  std::uint32_t flagged = 0;
  for (std::uint32_t k = 0; k < kRows; ++k) {
    tick();
    flagged += (engine_.flags() & runlog::kRateLimited) != 0 ? 1U : 0U;
  }
  EXPECT_EQ(flagged, kRows - 1);
}

TEST_F(EngineTest, LargestMoveNamesItsRowAndClampingNeedsTheBaseline) {
  EngineConfig c = small_config();
  table_[2 * 5] = 30.0;  // channel 0: 1 2 3 4 5 30 7 8 — up 25 at row 5, down 23 at row 6
  c.input[0].max_move = 10.0;
  const Distortion dry = predict_distortion(c, table(), {});
  EXPECT_DOUBLE_EQ(dry.channel[0].largest_move, 25.0);
  EXPECT_EQ(dry.channel[0].largest_move_row, 5U);
  EXPECT_EQ(dry.channel[0].rate_limited_rows, 1U);     // row 5 reaches 15; 15 → 7 is allowed
  const std::array<double, 2> baseline = {80.0, 5.0};  // channel 0 limits [0, 100]
  const Distortion armed = predict_distortion(c, table(), baseline);
  EXPECT_TRUE(armed.clamping_known);
  EXPECT_EQ(armed.channel[0].clamped_rows, 1U);  // 80 + 30 > 100
  EXPECT_EQ(armed.channel[1].clamped_rows, 0U);
}

}  // namespace excite::engine::testing
