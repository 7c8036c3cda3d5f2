// SPDX-License-Identifier: MIT
#pragma once
// A small engine under test: 2 setpoints, values [y0, y1, readback0, readback1, echo, command],
// a table of 8 rows, and a field that answers like a PLC (readbacks = setpoints written,
// heartbeat echoed) so each test only states what differs.

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "firmware/engine/engine.hpp"

namespace excite::engine::testing {

inline constexpr std::uint32_t kY0 = 0;
inline constexpr std::uint32_t kY1 = 1;
inline constexpr std::uint32_t kRb0 = 2;
inline constexpr std::uint32_t kRb1 = 3;
inline constexpr std::uint32_t kEcho = 4;
inline constexpr std::uint32_t kCommand = 5;

inline EngineConfig small_config() {
  EngineConfig c;
  c.inputs = 2;
  c.values = 6;
  c.input[0] = {0.0, 100.0, 10.0, static_cast<std::int32_t>(kRb0)};
  c.input[1] = {-50.0, 50.0, 10.0, static_cast<std::int32_t>(kRb1)};
  c.test[kY0] = {true, 90.0, 110.0, 2.0};  // y0 must stay in [90, 110]
  c.ramp_ticks = 0;
  c.resume_dwell_ticks = 3;
  c.suspend_timeout_ticks = 20;
  c.comm_fail_limit = 2;
  c.heartbeat_echo = static_cast<std::int32_t>(kEcho);
  c.heartbeat_max_lag = 2;
  c.command_value = static_cast<std::int32_t>(kCommand);
  return c;
}

struct Field {
  std::array<double, 6> values{100.0, 0.0, 40.0, 5.0, 0.0, 0.0};
  bool ok = true;
  bool echo = true;
};

class EngineTest : public ::testing::Test {
 protected:
  // Table: channel 0 = +1, +2, …, +8; channel 1 = −1, −2, …, −8.
  void SetUp() override {
    for (std::uint32_t k = 0; k < kRows; ++k) {
      table_[2 * k] = k + 1.0;
      table_[2 * k + 1] = -(k + 1.0);
    }
  }

  signal::ConstTableView table() const { return {table_.data(), 2, kRows}; }

  void configure(const EngineConfig& c = small_config()) {
    ASSERT_TRUE(engine_.configure(c, table())) << "configure";
  }

  void arm() { ASSERT_TRUE(engine_.arm(field_.values)); }

  void configure_arm_start(const EngineConfig& c = small_config()) {
    configure(c);
    arm();
    engine_.command(Command::start);
  }

  // One tick: compute, the field takes the setpoints (readback) and echoes the heartbeat.
  // `skipped`: grid points the clock passed before this tick (a loop overrun).
  const TickOutput& tick(std::uint64_t skipped = 0) {
    const TickOutput& out = engine_.compute(skipped);
    last_ = out;
    if (out.write && field_.ok) {
      field_.values[kRb0] = out.setpoint[0];
      field_.values[kRb1] = out.setpoint[1];
      if (field_.echo) field_.values[kEcho] = out.heartbeat;
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
  Field field_;
  TickOutput last_;
};

}  // namespace excite::engine::testing
