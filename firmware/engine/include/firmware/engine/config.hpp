// SPDX-License-Identifier: MIT
#pragma once
// What the engine needs to know besides the plan: absolute limits of every setpoint, the
// test limits of the controlled variables, ramps, dwell and timeouts — all in ticks and in
// each channel's engineering unit. The app fills it from the gateway configuration file
// (firmware/app/README.md), converting seconds to ticks.

#include <array>
#include <cstdint>

#include "firmware/signal/recipe.hpp"
#include "firmware/signal/status.hpp"

namespace excite::engine {

using signal::Status;
using signal::StatusCode;

inline constexpr std::uint32_t kMaxInputs = signal::kMaxChannels;  // setpoints = plan channels
inline constexpr std::uint32_t kMaxValues = 32;                    // values read per tick
inline constexpr std::int32_t kNone = -1;                          // "no value index"
inline constexpr std::uint32_t kMaxReadbackLag = 16;               // readback_lag_ticks ≤ this
/// Longest ramp, dwell or timeout in ticks (a day at 1 ms ticks ≈ 8.6e7; a gateway config
/// range check keeps the seconds → ticks conversion well inside uint32).
inline constexpr std::uint32_t kMaxDurationTicks = 1'000'000'000;
/// Largest heartbeat_max_lag: well inside the 16-bit heartbeat's wrap (65536).
inline constexpr std::uint32_t kMaxHeartbeatLagTicks = 30000;

/// One setpoint (a plan channel), absolute engineering units.
struct InputLimits {
  double min = 0.0;               // lowest setpoint ever written
  double max = 0.0;               // highest setpoint ever written; min ≤ max
  double max_move = 0.0;          // largest |Δsetpoint| per tick, > 0
  std::int32_t readback = kNone;  // value index whose reading at arm is the baseline
  // Verified writes: a readback agrees with the setpoint written when
  //   |read − written| ≤ readback_abs_tol + readback_rel_tol · |written|
  // (the register types' resolution: float32 2^-23 relative, a scaled integer one raw step).
  double readback_abs_tol = 0.0;  // engineering units, ≥ 0
  double readback_rel_tol = 0.0;  // ≥ 0
};

/// Test limits of one value (a controlled variable), absolute engineering units.
struct TestLimit {
  bool enabled = false;
  double low = 0.0;  // outside [low, high] → suspend
  double high = 0.0;
  double hysteresis = 0.0;  // resume only inside [low + h, high − h]; 0 ≤ 2h < high − low
};

/// Closed loop (issue 42 §2): the gateway writes test offsets to a running controller and
/// reads back what it did. Value indices (kNone: not read) of the controller's registers
/// (sim/server/README.md, "Closed loop"; a DCS maps the same): its mode (0 off, 1 control,
/// 2 test, 3 suspended) and each MV's status (0 ok, 1 clamped low, 2 clamped high,
/// 3 windup, 4 manual) are watched; its moves, the applied MVs and the setpoints in force
/// are data for the run log (TickRecord). A clamped or wound-up MV, or the controller out
/// of control/test (manual, off, suspended), suspends the test (kReasonController) and,
/// after timeout_ticks of it, aborts (Outcome::aborted_on_controller). Safe then also
/// needs the controller in its mode (control or test) at the confirming readbacks.
struct ControllerWatch {
  std::int32_t mode = kNone;  // kNone: an open-loop run (nothing below applies)
  std::uint32_t mvs = 0;      // MVs with a status value, ≤ kMaxInputs
  std::array<std::int32_t, kMaxInputs> status{};
  std::array<std::int32_t, kMaxInputs> move{};     // kNone where not read
  std::array<std::int32_t, kMaxInputs> applied{};  // kNone where not read
  std::uint32_t cvs = 0;                           // setpoints in force read, ≤ kMaxInputs
  std::array<std::int32_t, kMaxInputs> setpoint{};
  std::uint32_t timeout_ticks = 0;  // suspended for the controller this long → abort; 0 never
  std::int64_t timeout_ns = 0;      // the same on the real clock (lock-step); 0: none
};

enum class CommLossAction : std::uint8_t {
  hold,              // keep the last setpoints while the link is down
  ramp_to_baseline,  // ramp the excitation out, as for a test-limit suspension
};

struct EngineConfig {
  std::uint32_t inputs = 0;  // setpoints written per tick, 1..kMaxInputs
  std::uint32_t values = 0;  // values read per tick, 1..kMaxValues
  std::array<InputLimits, kMaxInputs> input{};
  std::array<TestLimit, kMaxValues> test{};
  std::uint32_t ramp_ticks = 0;          // excitation 0 → full (and back) over this many ticks
  std::uint32_t resume_dwell_ticks = 1;  // all back inside (with hysteresis) this long → resume
  std::uint32_t suspend_timeout_ticks = 0;  // suspended this long → abort; 0 = never
  std::uint32_t comm_fail_limit = 3;        // failed exchanges in a row → comm loss, ≥ 1
  std::int32_t heartbeat_echo = kNone;      // value index where the peer echoes the heartbeat
  std::uint32_t heartbeat_max_lag = 0;      // echo older than this many ticks → stale (comm loss)
  std::int32_t command_value = kNone;       // value index of the operator command register
  // The command register is acknowledged by clearing it: after a reading that is not 0
  // the Runner writes 0 back (command_clear_due / command_cleared), so each command written
  // is a new edge, the same code too (issue 39 §3).
  bool acknowledge_command = false;
  CommLossAction comm_loss = CommLossAction::hold;
  // Verified writes (off by default in the engine; excite-gateway always turns them on).
  bool verify_readbacks = false;
  // The reading of tick k reflects the write of tick k − (lag − 1): 1 = the same exchange
  // (the Runner writes, then reads). 1 … kMaxReadbackLag.
  std::uint32_t readback_lag_ticks = 1;
  // More than this many consecutive mismatching ticks on one setpoint → readback fault.
  std::uint32_t readback_mismatch_limit = 3;
  // Safe means confirmed and held (issue 28 item 2). 0: the older window (README). Else,
  // from the tick the output reaches the baseline, the baseline must be read back on two
  // exchanges at least confirm_hold_ticks apart with no failed exchange between them (a
  // failure means a reconnect: confirmation starts afresh after it) within
  // confirm_timeout_ticks; otherwise safe_unconfirmed. Mismatches while returning are then
  // stale writes being undone (the baseline is written every tick), counted, not faults.
  std::uint32_t confirm_timeout_ticks = 0;
  std::uint32_t confirm_hold_ticks = 1;  // ≥ 1
  // Plan segments (Engine::stage): an approved staged table is taken at a period boundary
  // of the running table — after a row r with (r + 1) % segment_period_rows == 0 — or
  // after its last row. 0: at the end of the running table only.
  std::uint32_t segment_period_rows = 0;
  // Awaiting the next segment (Engine::awaiting_segment): when the running table's last row
  // has been written and no approved segment is staged, the run does not complete at once
  // but holds the operating point (excitation 0: the baseline, max_move still applying) for
  // up to this many ticks, counted on the clock, each row flagged kSuspended, and switches
  // to a segment approved meanwhile; then it completes as without. 0: it completes at once.
  std::uint32_t segment_await_ticks = 0;
  // Timeouts on the real clock (issue 39 §2), for a loop whose ticks are not real time
  // (lock-step: the peer owns the clock). Once the loop hands the engine the real time
  // (Engine::set_real_time), the suspension timeout and the confirmation time end when
  // these have passed on the real clock or their ticks have passed on the peer's clock,
  // whichever comes first, and a failed exchange adds no tick (the peer's time stood
  // still). Nanoseconds; 0: no such limit (the suspension: never, as its ticks).
  std::int64_t suspend_timeout_ns = 0;
  std::int64_t confirm_timeout_ns = 0;
  ControllerWatch controller{};  // closed loop; controller.mode == kNone: open loop
};

/// Ok, or the first broken rule naming the field ("input[1].max_move = 0, expected > 0").
Status validate(const EngineConfig& config);

}  // namespace excite::engine
