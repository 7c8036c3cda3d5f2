// SPDX-License-Identifier: MIT
// The cyclic path allocates nothing (STYLE.md practice 5): operator new replaced and the
// malloc family interposed, counted over 10 000+ ticks of the gateway component's run()
// (Runner: engine + simlink plant + log ring + range-end watch) through excursions, comm
// loss (then reads before writing again), stale echo, skipped ticks (the clock jumps past
// deadlines) and operator commands; a segment switch; and awaiting a segment at the table's
// end (segments.await_s), holding the baseline (real time) or without ticking (lock-step). The ring
// is drained on this thread between batches (no log thread), so only the cyclic path runs while
// counting.
#include <chrono>
#include <fstream>
#include <thread>

#include "counting_malloc.hpp"
#include "counting_new.hpp"
#include "firmware/runlog/format.hpp"
#include "gateway_fixture.hpp"

namespace excite::testing {

class Faults final : public app::TickObserver {
 public:
  Faults(sim::simlink::SimLinkFieldBus& bus, app::CommandMailbox& commands,
         hal::VirtualClock& clock, hal::Nanoseconds period)
      : bus_(bus), commands_(commands), clock_(clock), period_(period) {}
  void after_tick(const engine::Engine&, std::uint64_t tick) noexcept override {
    switch (tick % 500) {
      case 100:
        bus_.set_disturbance(0, 2.0 * kTestBand);
        break;
      case 150:
        bus_.set_disturbance(0, 0.0);
        break;
      case 200:
        bus_.drop(5);
        break;
      case 300:
        bus_.freeze_echo(true);
        break;
      case 310:
        bus_.freeze_echo(false);
        break;
      case 350:
        clock_.advance(period_ * 7);  // this tick ran long: 7 grid points are skipped
        break;
      case 400:
        commands_.post(engine::Command::suspend);
        break;
      case 420:
        commands_.post(engine::Command::resume);
        break;
      case 440:  // the command register, acknowledged: the gateway writes 0 back
        bus_.set_command(2.0);
        break;
      case 460:
        bus_.set_command(3.0);
        break;
      default:
        break;
    }
  }

 private:
  sim::simlink::SimLinkFieldBus& bus_;
  app::CommandMailbox& commands_;
  hal::VirtualClock& clock_;
  hal::Nanoseconds period_;
};

TEST_F(GatewayLoop, TenThousandTicksOfTheCyclicPathAllocateNothing) {
  config_.suspend_timeout_s = 0.0;
  config_.values[9].acknowledge = true;  // the command register (gateway_fixture.hpp)
  // The plan lengthened to 12 000 rows so the run outlasts the measurement (set-up may
  // allocate); the gateway component is built exactly as excite-gateway builds it.
  plan_file_ = example_plan_file(12000);
  ASSERT_TRUE(start_up());
  Faults faults(*bus_, commands_, clock_, gateway_->period());
  gateway_->set_observer(&faults);
  commands_.post(engine::Command::start);
  engine::LogRingBase& ring = gateway_->log_ring();

  // The consumer side runs between batches (same thread) so the ring never overruns.
  engine::TickRecord sink;
  long new_count = 0;
  long malloc_count = 0;
  std::uint64_t ticks = 0;
  std::uint64_t reverified = 0;
  for (int batch = 0; batch < 25; ++batch) {
    const long n0 = excite::test::allocations();
    const long m0 = excite::test::mallocs();
    const app::RunStats stats = gateway_->run(commands_, nullptr, 500);
    ticks += stats.ticks;
    reverified += stats.reverified;
    new_count += excite::test::allocations() - n0;
    malloc_count += excite::test::mallocs() - m0;
    while (ring.pop(sink)) {
    }
  }
  EXPECT_GE(ticks, 10000U);
  EXPECT_EQ(new_count, 0);
  EXPECT_EQ(malloc_count, 0) << "(malloc interposed: " << excite::test::malloc_interposed() << ")";
  EXPECT_GT(engine().suspensions(), 40U);                 // the fault paths were taken
  EXPECT_GE(engine().commands_acknowledged(), 2U * 20U);  // the register cleared each time
  EXPECT_GT(bus_->dropped(), 50U);
  EXPECT_GT(reverified, 20U);                               // read before writing again
  EXPECT_GE(engine().rows_flagged(runlog::kSkipped), 20U);  // the skipped-tick path
  EXPECT_GE(engine().skipped_ticks(), 7U * 20U);
  EXPECT_EQ(ring.overruns(), 0U);
}

// A copy of the example plan staged as the next segment by the gateway's inbox thread (which
// allocates: it decodes and generates), the thread stopped before anything is counted.
bool stage_a_copy_of_the_plan(app::Gateway* gateway, const std::string& log_path) {
  const std::filesystem::path inbox = std::filesystem::path(log_path).replace_extension(".inbox");
  std::filesystem::create_directories(inbox);
  {
    const std::vector<std::uint8_t> next = example_plan_file();
    std::ofstream(inbox / "next.plan", std::ios::binary)
        .write(reinterpret_cast<const char*>(next.data()),
               static_cast<std::streamsize>(next.size()));
  }
  gateway->start_segments(inbox.string(), true, nullptr);
  for (int i = 0; i < 500 && gateway->segments()->staged() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  gateway->stop_segments();
  std::filesystem::remove_all(inbox);
  EXPECT_EQ(gateway->segments()->staged(), 1U);
  return gateway->segments()->staged() == 1U;
}

// Plan segments: a segment staged by the inbox thread (which allocates: it decodes and
// generates; stopped before counting) is handed to the tick, approved and switched to at the
// end of the running table, on the cyclic path without an allocation.
TEST_F(GatewayLoop, ASegmentSwitchOnTheCyclicPathAllocatesNothing) {
  config_.suspend_timeout_s = 0.0;
  ASSERT_TRUE(start_up());  // the example plan: 4080 rows
  ASSERT_TRUE(stage_a_copy_of_the_plan(gateway_.get(), log_path_));
  engine::LogRingBase& ring = gateway_->log_ring();
  engine::TickRecord sink;
  commands_.post(engine::Command::start);
  long new_count = 0;
  long malloc_count = 0;
  for (int batch = 0; batch < 10; ++batch) {
    if (batch == 1) commands_.post(engine::Command::approve);
    const long n0 = excite::test::allocations();
    const long m0 = excite::test::mallocs();
    (void)gateway_->run(commands_, nullptr, 500);
    new_count += excite::test::allocations() - n0;
    malloc_count += excite::test::mallocs() - m0;
    while (ring.pop(sink)) {
    }
  }
  EXPECT_EQ(engine().segment(), 1U)  // the switch was really taken (after row 4079)
      << engine::to_string(engine().state()) << " row " << engine().row() << " staged "
      << engine().segment_staged() << " approved " << engine().segment_approved();
  EXPECT_EQ(new_count, 0);
  EXPECT_EQ(malloc_count, 0) << "(malloc interposed: " << excite::test::malloc_interposed() << ")";
}

// Awaiting the next segment (segments.await_s): a clock for the lock-step wait that posts
// `approve` after its 10th sleep, as an operator would while the gateway stands still.
class ApprovingClock final : public hal::Clock {
 public:
  explicit ApprovingClock(app::CommandMailbox& commands) : commands_(commands) {}
  [[nodiscard]] hal::Nanoseconds now() const noexcept override { return clock_.now(); }
  void sleep_until(hal::Nanoseconds deadline) noexcept override {
    clock_.sleep_until(deadline);
    if (++sleeps_ == 10) commands_.post(engine::Command::approve);
  }
  std::uint64_t sleeps() const noexcept { return sleeps_; }

 private:
  app::CommandMailbox& commands_;
  hal::VirtualClock clock_;
  std::uint64_t sleeps_ = 0;
};

// Posts `approve` once the engine has held the baseline for 5 ticks (real time).
class ApproveAfterFiveHeld final : public app::TickObserver {
 public:
  explicit ApproveAfterFiveHeld(app::CommandMailbox& commands) : commands_(commands) {}
  void after_tick(const engine::Engine& engine, std::uint64_t) noexcept override {
    if (engine.awaited_ticks() == 5 && !posted_) {
      commands_.post(engine::Command::approve);
      posted_ = true;
    }
  }

 private:
  app::CommandMailbox& commands_;
  bool posted_ = false;
};

class AwaitLoop : public GatewayLoop {
 protected:
  // The example plan (4080 rows) armed with segments.await_s = 1 h (60 ticks of 1 min) and a
  // copy of it staged by the inbox thread, not approved (the thread stopped before counting).
  bool start_with_a_staged_segment() {
    config_.suspend_timeout_s = 0.0;
    config_.segment_await_s = 3600.0;
    return start_up() && stage_a_copy_of_the_plan(gateway_.get(), log_path_);
  }

  // Runs 10 batches of 500 ticks, draining the ring between them; allocations counted.
  void run_counting(long& new_count, long& malloc_count, app::RunStats& last) {
    engine::LogRingBase& ring = gateway_->log_ring();
    engine::TickRecord sink;
    commands_.post(engine::Command::start);
    for (int batch = 0; batch < 10; ++batch) {
      const long n0 = excite::test::allocations();
      const long m0 = excite::test::mallocs();
      last = gateway_->run(commands_, nullptr, 500);
      new_count += excite::test::allocations() - n0;
      malloc_count += excite::test::mallocs() - m0;
      while (ring.pop(sink)) {
      }
    }
  }
};

// Real time: at the table's end the engine holds the baseline, ticking (5 rows), until the
// approval; then the segment runs. Nothing allocated.
TEST_F(AwaitLoop, HoldingTheBaselineForASegmentAllocatesNothing) {
  ASSERT_TRUE(start_with_a_staged_segment());
  ApproveAfterFiveHeld approver(commands_);
  gateway_->set_observer(&approver);
  long new_count = 0;
  long malloc_count = 0;
  app::RunStats stats;
  run_counting(new_count, malloc_count, stats);
  EXPECT_EQ(engine().segment(), 1U);
  EXPECT_EQ(engine().awaited_ticks(), 5U);
  EXPECT_EQ(engine().rows_flagged(runlog::kSuspended), 5U);
  EXPECT_EQ(stats.segment_waits, 0U);  // it never stopped ticking
  EXPECT_EQ(new_count, 0);
  EXPECT_EQ(malloc_count, 0) << "(malloc interposed: " << excite::test::malloc_interposed() << ")";
}

// Lock-step: at the table's end the loop stops ticking and waits on its real clock (here a
// virtual one that approves after 10 ms), then the segment runs from row 0; no row held.
TEST_F(AwaitLoop, AwaitingASegmentWithoutTickingAllocatesNothing) {
  ASSERT_TRUE(start_with_a_staged_segment());
  ApprovingClock real(commands_);
  gateway_->await_segments_on(&real);
  long new_count = 0;
  long malloc_count = 0;
  app::RunStats stats;
  run_counting(new_count, malloc_count, stats);
  EXPECT_EQ(engine().segment(), 1U);
  EXPECT_EQ(engine().awaited_ticks(), 0U);
  EXPECT_EQ(stats.segment_waits, 1U);
  EXPECT_EQ(real.sleeps(), 10U);
  EXPECT_EQ(stats.segment_wait, std::chrono::milliseconds(10));
  EXPECT_EQ(new_count, 0);
  EXPECT_EQ(malloc_count, 0) << "(malloc interposed: " << excite::test::malloc_interposed() << ")";
}

}  // namespace excite::testing
