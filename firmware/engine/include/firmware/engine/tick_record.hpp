// SPDX-License-Identifier: MIT
#pragma once
// One tick as the run log records it: what was written, what was read, the state, flags.

#include <array>
#include <cstdint>

#include "firmware/engine/config.hpp"
#include "firmware/engine/state.hpp"

namespace excite::engine {

struct TickRecord {
  std::int64_t time_ns = 0;   // the tick's nominal time (clock epoch)
  std::uint64_t tick = 0;     // ticks since arm: 0, 1, 2, … (the run log's k)
  std::uint32_t row = 0;      // table row k written this tick (frozen while suspended)
  std::uint32_t segment = 0;  // plan segment of that row: 0 the plan started with, then 1, 2, …
  State state = State::configured;
  std::uint32_t flags = 0;              // runlog::Flag bits
  std::array<double, kMaxInputs> du{};  // setpoint − baseline
  std::array<double, kMaxInputs> u{};   // setpoint written (absolute)
  std::array<double, kMaxValues> dy{};  // value − value at arm (last good on comm loss)
  // Closed loop (EngineConfig::controller; the run-log v4 columns, agreed in issue 41/42):
  // r: the test signal written (the offsets: du above, per written channel); uc: the
  // controller's move and du_applied: the MV the plant got, per MV (deviations, as read);
  // ysp: the setpoints in force per CV; st: each MV's status; mode: the controller's mode.
  // Read values are the last good ones (as dy). All zero in an open-loop run.
  bool closed_loop = false;
  std::uint32_t mvs = 0;
  std::uint32_t cvs = 0;
  std::array<double, kMaxInputs> r{};
  std::array<double, kMaxInputs> uc{};
  std::array<double, kMaxInputs> du_applied{};
  std::array<double, kMaxInputs> ysp{};
  std::array<std::uint8_t, kMaxInputs> st{};
  std::uint8_t mode = 0;
};

}  // namespace excite::engine
