// SPDX-License-Identifier: MIT
#pragma once
// An engine in closed loop under test: 2 test offsets (baseline 0) and a field that answers
// like a DCS running a controller: values [y0, rb0, rb1, echo, mode, st0, st1, uc0, uc1,
// du0, du1, ysp0]: the offsets read back as written, the heartbeat echoed, the controller in
// control with every MV ok until a test says otherwise.

#include <gtest/gtest.h>

#include <array>

#include "firmware/engine/engine.hpp"

namespace excite::engine::testing {

inline constexpr std::uint32_t kCy = 0;
inline constexpr std::uint32_t kRbOff0 = 1;
inline constexpr std::uint32_t kRbOff1 = 2;
inline constexpr std::uint32_t kEchoCl = 3;
inline constexpr std::uint32_t kMode = 4;
inline constexpr std::uint32_t kStatus0 = 5;
inline constexpr std::uint32_t kStatus1 = 6;
inline constexpr std::uint32_t kMove0 = 7;
inline constexpr std::uint32_t kApplied0 = 9;
inline constexpr std::uint32_t kSetpointInForce = 11;
inline constexpr std::uint32_t kClosedValues = 12;

inline EngineConfig closed_config() {
  EngineConfig c;
  c.inputs = 2;
  c.values = kClosedValues;
  c.input[0] = {-10.0, 10.0, 10.0, static_cast<std::int32_t>(kRbOff0)};
  c.input[1] = {-10.0, 10.0, 10.0, static_cast<std::int32_t>(kRbOff1)};
  c.ramp_ticks = 0;
  c.resume_dwell_ticks = 3;
  c.suspend_timeout_ticks = 0;
  c.comm_fail_limit = 2;
  c.heartbeat_echo = static_cast<std::int32_t>(kEchoCl);
  c.heartbeat_max_lag = 2;
  c.verify_readbacks = true;
  c.confirm_timeout_ticks = 10;
  c.confirm_hold_ticks = 2;
  ControllerWatch& w = c.controller;
  w.status.fill(kNone);
  w.move.fill(kNone);
  w.applied.fill(kNone);
  w.setpoint.fill(kNone);
  w.mode = static_cast<std::int32_t>(kMode);
  w.mvs = 2;
  w.status[0] = static_cast<std::int32_t>(kStatus0);
  w.status[1] = static_cast<std::int32_t>(kStatus1);
  w.move[0] = static_cast<std::int32_t>(kMove0);
  w.move[1] = static_cast<std::int32_t>(kMove0 + 1);
  w.applied[0] = static_cast<std::int32_t>(kApplied0);
  w.applied[1] = static_cast<std::int32_t>(kApplied0 + 1);
  w.cvs = 1;
  w.setpoint[0] = static_cast<std::int32_t>(kSetpointInForce);
  w.timeout_ticks = 5;
  return c;
}

struct ClosedLoopField {
  std::array<double, kClosedValues> values{0.5, 0, 0, 0, 1.0, 0, 0, 0, 0, 0, 0, 0};
  bool ok = true;
};

class ClosedLoopTest : public ::testing::Test {
 protected:
  // Table: channel 0 = +1 … +8 (an MV offset), channel 1 = −1 … −8.
  void SetUp() override {
    for (std::uint32_t k = 0; k < kRows; ++k) {
      table_[2 * k] = k + 1.0;
      table_[2 * k + 1] = -(k + 1.0);
    }
  }
  void start(const EngineConfig& c = closed_config()) {
    ASSERT_TRUE(validate(c)) << validate(c).message();
    ASSERT_TRUE(engine_.configure(c, {table_.data(), 2, kRows}));
    ASSERT_TRUE(engine_.arm(field_.values));
    engine_.command(Command::start);
  }
  const TickOutput& tick() {
    const TickOutput& out = engine_.compute();
    last_ = out;
    if (out.write && field_.ok) {
      field_.values[kRbOff0] = out.setpoint[0];
      field_.values[kRbOff1] = out.setpoint[1];
      field_.values[kEchoCl] = out.heartbeat;
    }
    engine_.observe(field_.ok, field_.values);
    return last_;
  }
  void ticks(int n) {
    for (int i = 0; i < n; ++i) tick();
  }

  static constexpr std::uint32_t kRows = 8;
  std::array<double, 2 * kRows> table_{};
  Engine engine_;
  ClosedLoopField field_;
  TickOutput last_;
};

}  // namespace excite::engine::testing
