// SPDX-License-Identifier: MIT
// excite-plant's closed loop in its parts (issue 42 §1): the controller in the loop
// (ClosedLoop: applied MV, statuses, modes, the watchdog's clear), its registers (the default
// map under a controller, the three addresses required with a controller and refused without,
// the heartbeat above the offsets, overlaps), the configuration written and read back, and no
// allocation in the loop's step.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "counting_new.hpp"
#include "sim/server/closed_loop.hpp"
#include "sim/server/config_writer.hpp"
#include "sim/server/default_map.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

// A controller whose move is whatever the test sets: the loop's arithmetic alone.
class FixedController : public control::Controller {
 public:
  explicit FixedController(std::vector<double> move) : move_(std::move(move)) {
    status_.assign(move_.size(), control::MvStatus::ok);
  }
  int inputs() const noexcept override { return static_cast<int>(move_.size()); }
  int outputs() const noexcept override { return 1; }
  double sample_time_min() const noexcept override { return 1.0; }
  void reset() noexcept override {}
  control::StepReport step(std::span<const double>, std::span<const double> y_sp,
                           std::span<const double>, std::span<double> u) noexcept override {
    last_sp = y_sp.empty() ? 0.0 : y_sp[0];
    ++steps;
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = move_[i];
    return {};
  }
  std::span<const control::MvStatus> mv_status() const noexcept override { return status_; }

  std::vector<double> move_;
  std::vector<control::MvStatus> status_;
  double last_sp = 0.0;
  int steps = 0;
};

struct Loop {
  FixedController* controller;
  ClosedLoop loop;
};

Loop make_loop(std::vector<double> move) {
  auto c = std::make_unique<FixedController>(std::move(move));
  FixedController* raw = c.get();
  return {raw, ClosedLoop(std::move(c), {-1.0, -1.0}, {1.0, 1.0})};
}

TEST(ClosedLoop, TheAppliedMvIsTheMovePlusTheOffsetInsideItsLimits) {
  Loop l = make_loop({0.25, -0.5});
  const std::vector<double> y{0.0};
  const std::vector<double> sp{0.3};
  l.loop.step(y, 1, std::vector<double>{0.5, 0.0}, sp);
  EXPECT_EQ(l.loop.applied()[0], 0.75);
  EXPECT_EQ(l.loop.applied()[1], -0.5);
  EXPECT_EQ(l.loop.status()[0], LoopStatus::ok);
  EXPECT_EQ(l.loop.mode(), LoopMode::test) << "an offset in force";
  EXPECT_EQ(l.controller->last_sp, 0.3) << "the setpoint offset is the controller's setpoint";
  EXPECT_EQ(l.loop.setpoints()[0], 0.3);
  l.loop.step(y, 1, std::vector<double>{0.75, 0.0}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.applied()[0], 1.0) << "exactly on the limit";
  EXPECT_EQ(l.loop.status()[0], LoopStatus::clamped_high);
  l.loop.step(y, 1, std::vector<double>{0.9, -0.6}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.applied()[0], 1.0) << "clamped";
  EXPECT_EQ(l.loop.status()[0], LoopStatus::windup) << "the move plus the offset ask beyond";
  EXPECT_EQ(l.loop.applied()[1], -1.0);
  EXPECT_EQ(l.loop.status()[1], LoopStatus::windup);
  l.loop.step(y, 1, std::vector<double>{0.0, 0.0}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.mode(), LoopMode::control) << "no offset: control";
  EXPECT_EQ(l.loop.status()[0], LoopStatus::ok);
}

TEST(ClosedLoop, ManualHoldsEveryMvAndTheControllerStandsStill) {
  Loop l = make_loop({0.25, -0.5});
  const std::vector<double> y{0.0};
  l.loop.step(y, 1, std::vector<double>{0.1, 0.0}, std::vector<double>{0.0});
  const int steps = l.controller->steps;
  l.controller->move_ = {0.9, 0.9};
  l.loop.step(y, 0, std::vector<double>{0.3, 0.3}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.mode(), LoopMode::off);
  EXPECT_EQ(l.loop.applied()[0], 0.35) << "held where it was";
  EXPECT_EQ(l.loop.status()[0], LoopStatus::manual);
  EXPECT_EQ(l.loop.status()[1], LoopStatus::manual);
  EXPECT_EQ(l.controller->steps, steps);
  l.loop.step(y, 7, std::vector<double>{0.3, 0.3}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.mode(), LoopMode::off) << "not a switch value: the last request stands";
  l.loop.clear_offsets();
  EXPECT_EQ(l.loop.applied()[0], 0.35) << "the watchdog leaves a manual MV alone";
  l.loop.step(y, 3, std::vector<double>{0.3, 0.3}, std::vector<double>{0.0});
  EXPECT_EQ(l.loop.mode(), LoopMode::suspended);
  EXPECT_EQ(l.loop.applied()[0], 0.25) << "suspended: the last move, without the offset";
  EXPECT_EQ(l.controller->steps, steps);
  l.loop.step(y, 1, std::vector<double>{0.3, 0.3}, std::vector<double>{0.0});
  EXPECT_EQ(l.controller->steps, steps + 1);
  EXPECT_EQ(l.loop.applied()[0], 1.0);  // 0.9 + 0.3, clamped
}

TEST(ClosedLoop, TheWatchdogsClearDropsTheOffsetsAndKeepsControl) {
  Loop l = make_loop({0.25, -0.5});
  l.loop.step(std::vector<double>{0.0}, 1, std::vector<double>{0.5, 0.1}, std::vector<double>{0.2});
  ASSERT_EQ(l.loop.mode(), LoopMode::test);
  l.loop.clear_offsets();
  EXPECT_EQ(l.loop.mode(), LoopMode::control);
  EXPECT_EQ(l.loop.applied()[0], 0.25) << "the controller's move alone, at once";
  EXPECT_EQ(l.loop.offsets()[0], 0.0);
  EXPECT_EQ(l.loop.setpoints()[0], 0.0);
}

TEST(ClosedLoop, AStepAllocatesNothing) {
  Loop l = make_loop({0.25, -0.5});
  const std::vector<double> y{0.0};
  const std::vector<double> o{0.1, 0.2};
  const std::vector<double> sp{0.3};
  const long before = excite::test::allocations();
  for (int k = 0; k < 1000; ++k) {
    l.loop.step(y, static_cast<std::uint16_t>(k % 4), o, sp);
    l.loop.clear_offsets();
  }
  EXPECT_EQ(excite::test::allocations() - before, 0);
}

ServerConfig closed_config(bool lockstep_ok = true) {
  ServerConfig c;
  c.plant.library = "woodberry2x2";
  c.plant.controller = "pi.toml";
  c.registers = default_registers(2, 2, {}, {}, true);
  (void)lockstep_ok;
  return c;
}

TEST(ClosedLoopLayout, TheDefaultMapUnderAControllerIsPlacedAsDocumented) {
  const ServerLayout layout = compile_layout(closed_config(), 2, 2, true, "plant.toml");
  ASSERT_TRUE(layout.closed_loop);
  const ClosedLoopLayout& l = *layout.closed_loop;
  EXPECT_EQ(l.mv_offsets[1].address, 502U);
  EXPECT_EQ(l.sp_offsets[0].address, 504U);
  EXPECT_EQ(layout.heartbeat_address, 508U) << "above the offsets: written last";
  EXPECT_EQ(l.moves[0].address, 500U);
  EXPECT_TRUE(l.moves[0].input_table);
  EXPECT_EQ(l.applied[0].address, 504U);
  EXPECT_EQ(l.setpoints[1].address, 510U);
  EXPECT_EQ(l.status[1].address, 513U);
  EXPECT_EQ(l.mode.address, 514U);
  EXPECT_EQ(l.controller_switch.address, 410U);
  RegisterImage image(layout, {0.0, 0.0}, {0.0, 0.0});
  EXPECT_EQ(image.controller_switch(), 1) << "the switch starts in control";
  EXPECT_EQ(image.input(514), 1) << "the mode reads control";
}

TEST(ClosedLoopLayout, ItsRegistersAreRequiredWithAControllerAndRefusedWithout) {
  ServerConfig c = closed_config();
  c.plant.controller.clear();
  try {
    compile_layout(c, 2, 2, true, "plant.toml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "plant.toml: registers.offset_address = 500, expected a controller to serve "
                 "the closed-loop registers (plant.controller or --controller FILE), or no "
                 "such key");
  }
  c = closed_config();
  c.registers.controller_switch_address.reset();
  EXPECT_THROW(compile_layout(c, 2, 2, true, "plant.toml"), std::invalid_argument);
  c = closed_config();
  c.registers.map.heartbeat_address = 104;  // below the offsets
  try {
    compile_layout(c, 2, 2, true, "plant.toml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("registers.heartbeat_address = 104, expected above "
                                         "every test-offset register in lock-step mode"),
              std::string::npos)
        << e.what();
  }
  c = closed_config();
  c.registers.controller_address = 202;  // over the outputs' input registers
  try {
    compile_layout(c, 2, 2, true, "plant.toml");
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected no overlap"), std::string::npos) << e.what();
  }
}

TEST(ClosedLoopLayout, TheWrittenConfigurationReadsBack) {
  ServerConfig c = closed_config();
  c.plant.sample_time_min = 1.0;
  const ServerConfig back = parse_server_config(format_server_config(c, "test"), "plant.toml");
  EXPECT_EQ(back.plant.controller, "pi.toml");
  EXPECT_EQ(back.registers.offset_address, 500U);
  EXPECT_EQ(back.registers.controller_address, 500U);
  EXPECT_EQ(back.registers.controller_switch_address, 410U);
  EXPECT_EQ(back.registers.map.heartbeat_address, 508U);
}

}  // namespace
}  // namespace excite::sim::server
