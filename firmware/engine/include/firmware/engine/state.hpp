// SPDX-License-Identifier: MIT
#pragma once
// The engine's lifecycle (README.md has the table: what holds in each state, what moves it).
//
//   configured ─arm→ armed ─start→ running ⇄ suspended
//   running ─table done→ completed ─→ returning ─baseline written and read back→ safe
//   returning ─baseline not confirmed in time→ safe_unconfirmed
//   armed | running | suspended ─abort / suspend timeout / readback fault / fault()→ aborted
//   aborted ─→ returning
//   configured ─abort→ safe (nothing was ever written)

#include <cstdint>

#include "firmware/runlog/format.hpp"

namespace excite::engine {

enum class State : std::uint8_t {
  configured,  // tables ready, bus open; nothing is written
  armed,       // baseline captured; the baseline and the heartbeat are written every tick
  running,     // the table streams: setpoint = baseline + ramp · table[k], k advancing
  suspended,   // k frozen; excitation ramps to the baseline (or holds on comm loss, if so set)
  completed,   // the last table row was written (one tick), then returning
  aborted,     // operator abort or suspension timeout (one tick), then returning
  returning,   // excitation ramps out to the baseline
  safe,        // the baseline was written and read back (confirmed); the run is over
  safe_unconfirmed,  // the baseline was written but never read back within the confirmation
                     // window (link down, readback mismatch): the field's state is unknown
};

/// The run is over (safe or safe_unconfirmed): nothing more will be written.
constexpr bool finished(State s) noexcept {
  return s == State::safe || s == State::safe_unconfirmed;
}

/// Operator commands (signals, command register, command line), applied at the next tick.
/// approve: the staged plan segment may be taken at the next boundary (Engine::stage);
/// ignored when no segment is staged (it never approves a segment not yet seen).
enum class Command : std::uint8_t {
  none = 0,
  start = 1,
  suspend = 2,
  resume = 3,
  abort = 4,
  approve = 5
};

/// Why a run is suspended: a bit set; the run resumes when it is empty.
enum SuspendReason : std::uint8_t {
  kReasonLimit = 1U << 0,       // a controlled variable left its test limits
  kReasonOperator = 1U << 1,    // suspend command, until a resume command
  kReasonComm = 1U << 2,        // communication lost (failed exchanges or stale heartbeat echo)
  kReasonController = 1U << 3,  // closed loop: an MV clamped or wound up, or the controller
                                // out of its mode (EngineConfig::controller)
};

/// How a run ended (meaningful in returning and safe).
enum class Outcome : std::uint8_t {
  none,
  completed,
  aborted_by_operator,
  aborted_on_timeout,
  readback_fault,  // a readback disagreed with the setpoint written (Engine::readback_fault())
  log_fault,       // the run log could not be written (disk full, file-size limit, I/O
                   // error): the loop stopped the excitation (Engine::fault)
  device_refused,  // the device answered a setpoint write with a refusal (Modbus exception
                   // 1, 2 or 3): the loop stopped the excitation (Engine::fault)
  foreign_writer,  // another master wrote this gateway's registers: a setpoint or the
                   // heartbeat changed to a value this gateway did not write
                   // (Engine::foreign_write())
  aborted_on_controller,  // closed loop: suspended for the controller (an MV clamped or wound
                          // up, the controller out of its mode) longer than its timeout
};

const char* to_string(State state) noexcept;
/// The run log's `state` column value (format v2) for an engine state: one for one.
runlog::RunState to_run_state(State state) noexcept;
const char* to_string(Command command) noexcept;
const char* to_string(Outcome outcome) noexcept;

/// The command register's integer code → Command (unknown codes → none).
Command command_from_code(std::int64_t code) noexcept;

}  // namespace excite::engine
