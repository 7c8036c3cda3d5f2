// SPDX-License-Identifier: MIT
// The engine's cyclic calls allocate nothing (STYLE.md practice 5): operator new and the
// malloc family are counted over 10 000 ticks through every state and fault path.
#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include "closed_loop_fixture.hpp"
#include "counting_malloc.hpp"
#include "counting_new.hpp"
#include "engine_fixture.hpp"
#include "firmware/engine/log_ring.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::engine::testing {

TEST_F(EngineTest, TenThousandTicksThroughEveryPathAllocateNothing) {
  EngineConfig c = small_config();
  c.suspend_timeout_ticks = 0;  // no abort: keep the run going
  c.ramp_ticks = 3;
  const std::vector<double> long_table(2 * 20000, 0.5);  // longer than the run
  ASSERT_TRUE(engine_.configure(c, {long_table.data(), 2, 20000}));
  arm();
  engine_.command(Command::start);
  auto ring = std::make_unique<LogRing<256>>();
  TickRecord sink;
  const long new_before = excite::test::allocations();
  const long malloc_before = excite::test::mallocs();
  for (int i = 0; i < 10000; ++i) {
    switch (i % 100) {  // excursions, comm loss, stale echo and operator commands
      case 10:
        field_.values[kY0] = 120.0;
        break;
      case 20:
        field_.values[kY0] = 100.0;
        break;
      case 40:
        field_.ok = false;
        break;
      case 45:
        field_.ok = true;
        break;
      case 60:
        field_.echo = false;
        break;
      case 66:
        field_.echo = true;
        break;
      case 80:
        engine_.command(Command::suspend);
        break;
      case 85:
        engine_.command(Command::resume);
        break;
      default:
        break;
    }
    if (i % 100 == 46) engine_.check_peer_continuity(field_.values);  // after the loss
    tick(i % 100 == 90 ? 3 : 0);  // a late tick: 3 grid points skipped
    ring->push(engine_.record(i));
    ring->pop(sink);
  }
  EXPECT_EQ(excite::test::allocations() - new_before, 0);
  EXPECT_EQ(excite::test::mallocs() - malloc_before, 0);
  EXPECT_GT(engine_.suspensions(), 100U);  // the paths were really taken
  EXPECT_GT(engine_.comm_losses(), 100U);
  EXPECT_EQ(engine_.ticks(), 10000U + 3U * 100U);  // on the clock: the skipped ones too
  EXPECT_EQ(engine_.rows_flagged(runlog::kSkipped), 100U);
}

// Plan segments: staging, approving and switching between two pre-allocated tables, every
// 50 rows (a period boundary), and a refused stage, allocate nothing either.
TEST_F(EngineTest, SegmentSwitchesAllocateNothing) {
  EngineConfig c = small_config();
  c.suspend_timeout_ticks = 0;
  c.segment_period_rows = 50;
  const std::vector<double> a(2 * 20000, 0.5);
  const std::vector<double> b(2 * 20000, -0.5);
  ASSERT_TRUE(engine_.configure(c, {a.data(), 2, 20000}));
  arm();
  engine_.command(Command::start);
  TickRecord sink;
  auto ring = std::make_unique<LogRing<256>>();
  const long new_before = excite::test::allocations();
  const long malloc_before = excite::test::mallocs();
  for (int i = 0; i < 10000; ++i) {
    if (i % 100 == 10) {
      const std::vector<double>& next = engine_.segment() % 2 == 0 ? b : a;
      (void)engine_.stage({next.data(), 2, 20000}, false);
      (void)engine_.stage({next.data(), 2, 20000}, false);  // refused: one is staged
    }
    if (i % 100 == 30) engine_.command(Command::approve);
    tick();
    ring->push(engine_.record(i));
    ring->pop(sink);
  }
  EXPECT_EQ(excite::test::allocations() - new_before, 0);
  EXPECT_EQ(excite::test::mallocs() - malloc_before, 0);
  EXPECT_EQ(engine_.segment(), 100U);  // the switches were really taken
}

}  // namespace excite::engine::testing

namespace excite::engine::testing {

// The counters themselves see allocations (so a zero above means something).
TEST(AllocationCountersTest, SeeOperatorNewAndMalloc) {
  const long new_before = excite::test::allocations();
  const long malloc_before = excite::test::mallocs();
  auto* p = new std::vector<int>(100);
  void* volatile raw = std::malloc(64);  // volatile: the call may not be elided
  EXPECT_GE(excite::test::allocations() - new_before, 2);
  if (excite::test::malloc_interposed()) {
    EXPECT_GE(excite::test::mallocs() - malloc_before, 1);
  }
  std::free(raw);
  delete p;
}

}  // namespace excite::engine::testing

namespace excite::engine::testing {

// Closed loop (issue 42 §2): the controller's mode and MV statuses watched every tick —
// clamped, wound up, manual, back in control —, its data recorded, suspensions and resumes:
// nothing allocated either.
TEST_F(ClosedLoopTest, ClosedLoopTicksAllocateNothing) {
  EngineConfig c = closed_config();
  c.controller.timeout_ticks = 0;  // never abort: keep the run going
  const std::vector<double> long_table(2 * 20000, 0.5);
  ASSERT_TRUE(engine_.configure(c, {long_table.data(), 2, 20000}));
  ASSERT_TRUE(engine_.arm(field_.values));
  engine_.command(Command::start);
  auto ring = std::make_unique<LogRing<256>>();
  TickRecord sink;
  const long new_before = excite::test::allocations();
  const long malloc_before = excite::test::mallocs();
  for (int i = 0; i < 10000; ++i) {
    switch (i % 100) {
      case 10:
        field_.values[kStatus0] = 1.0;  // clamped low
        break;
      case 20:
        field_.values[kStatus0] = 0.0;
        break;
      case 40:
        field_.values[kMode] = 0.0;  // manual
        field_.values[kStatus1] = 4.0;
        break;
      case 50:
        field_.values[kMode] = 2.0;  // back, testing
        field_.values[kStatus1] = 0.0;
        break;
      default:
        break;
    }
    field_.values[kMove0] = -0.001 * (i % 7);
    tick();
    ring->push(engine_.record(i));
    ring->pop(sink);
  }
  EXPECT_EQ(excite::test::allocations() - new_before, 0);
  EXPECT_EQ(excite::test::mallocs() - malloc_before, 0);
  EXPECT_EQ(engine_.mv_limited_episodes(), 100U);  // the paths were really taken
  EXPECT_EQ(engine_.controller_mode_losses(), 100U);
  EXPECT_TRUE(sink.closed_loop);
}

}  // namespace excite::engine::testing
