// SPDX-License-Identifier: MIT
#pragma once
// The gateway engine: the lifecycle (state.hpp) and the tick, as a pure state machine.
// It does no I/O: the loop around it (firmware/app) does, once per tick,
//
//   const TickOutput& out = engine.compute();          // setpoints for this tick
//   status = bus.write(out.setpoints(), out.heartbeat) // (skipped while !out.write)
//            then bus.read(values);
//   engine.observe(status == ok, values);              // test limits, comm guards, states
//   ring.push(engine.record(now));
//
// configure() and arm() run at start-up; compute(), observe(), command() and record() are
// the cyclic path: no allocation, no exceptions, no blocking, O(inputs + values).

#include <array>
#include <cstdint>
#include <span>

#include "firmware/engine/config.hpp"
#include "firmware/engine/state.hpp"
#include "firmware/engine/tick_record.hpp"
#include "firmware/signal/table.hpp"

namespace excite::engine {

/// What the loop writes this tick.
struct TickOutput {
  bool write = false;  // false only in configured: nothing goes to the field
  std::uint16_t heartbeat = 0;
  std::uint32_t inputs = 0;
  std::array<double, kMaxInputs> setpoint{};  // absolute, engineering units

  [[nodiscard]] std::span<const double> setpoints() const { return {setpoint.data(), inputs}; }
};

/// The first readback that disagreed with the setpoint written (verified writes).
struct ReadbackFault {
  bool valid = false;
  bool at_arm = false;         // found by verify_arm(): nothing was excited
  std::uint32_t input = 0;     // setpoint (plan channel) index
  std::int32_t value = kNone;  // value index of its readback
  double written = 0.0;        // the setpoint written, engineering units
  double read = 0.0;           // what came back
  std::uint64_t tick = 0;      // engine tick of the reading (0 at arm)
};

/// The first write this gateway did not make (issue 39 §1: one owner of a register block).
/// Before arm (check_quiet): a setpoint's readback or the heartbeat echo changed between two
/// reads while nothing was written. While running: the heartbeat echo moved to a value this
/// gateway never sent, or a setpoint's readback changed away from a value written on this
/// tick and the last (which it had read back) — another master writes the same registers.
struct ForeignWrite {
  bool valid = false;
  bool at_arm = false;         // found by check_quiet(): the gateway did not arm
  bool heartbeat = false;      // the heartbeat echo (value `value`), not a setpoint
  std::uint32_t input = 0;     // setpoint index (heartbeat == false)
  std::int32_t value = kNone;  // value index read: the setpoint's readback, or the echo
  double expected = 0.0;       // the first reading (at arm), what this gateway wrote, or the
                               // last heartbeat it sent
  double read = 0.0;           // what came back
  std::uint64_t tick = 0;      // engine tick of the reading (0 at arm)
};

class Engine {
 public:
  /// Takes the configuration (validate(config) must pass) and the table (not owned; kept
  /// alive by the caller; table.channels == config.inputs, already checked against the
  /// plan's deviation limits by load_plan). → configured.
  Status configure(const EngineConfig& config, signal::ConstTableView table);

  /// Captures the baseline from the live values (config.values of them, read from the
  /// field before anything was written): setpoint baseline from each input's readback,
  /// value baseline for dy. Refuses, writing nothing, when the engine is not configured,
  /// a value is not finite, a baseline lies outside [min, max], or baseline + the table's
  /// extremes would leave [min, max] of a channel. → armed.
  Status arm(std::span<const double> live_values);

  /// Verified writes at arm: `values` were read after the baseline (output()) was written
  /// once. Every readback must agree with its baseline within the resolution
  /// (InputLimits::readback_abs_tol/rel_tol), else the engine goes back to configured,
  /// readback_fault() names the setpoint, and an error is returned. Ok when
  /// config.verify_readbacks is off.
  Status verify_arm(std::span<const double> values);

  /// One owner (issue 39 §1): `first` and `second` (config.values each) were read a quiet
  /// interval apart with nothing written by this gateway. Every setpoint's readback must
  /// agree with itself (its readback tolerance) and the heartbeat echo must be unchanged;
  /// otherwise another master is writing: foreign_write() names the value and an error is
  /// returned (the caller refuses to arm, and arms on `second` only when this passed).
  /// Call while configured. Start-up only.
  Status check_quiet(std::span<const double> first, std::span<const double> second);

  /// The real time, for a loop whose ticks are not real time (lock-step): called before each
  /// compute() from then on, it turns on EngineConfig::suspend_timeout_ns and
  /// confirm_timeout_ns, and a failed exchange then adds no tick to those timeouts. Cyclic.
  void set_real_time(std::int64_t now_ns) noexcept {
    real_clock_ = true;
    now_ns_ = now_ns;
  }

  /// Queues an operator command, applied at the next compute() (the last one wins).
  /// Safe to call from the tick's thread only; the app funnels signals through an atomic.
  void command(Command c) noexcept { pending_ = c; }

  /// Stages the next plan segment's table (not owned; kept alive and unchanged by the caller
  /// until segment() has moved past it): already checked by the caller against the running
  /// plan (channels, limits, sample time: check_segment, segment.hpp). It is taken only when
  /// approved (here, or later by Command::approve), at the next boundary of the running
  /// table (EngineConfig::segment_period_rows, or its end): the row written after the
  /// switch is row 0 of the new table, the baseline and the ramp are unchanged, and
  /// max_move still limits every move. Refused (nothing staged) when a segment is already
  /// staged, the run is not armed, running or suspended, or the table's shape differs.
  /// Cyclic path: O(1), no allocation.
  Status stage(signal::ConstTableView next, bool approved) noexcept;

  /// Whether the next compute() would hold for the next segment instead of writing a table
  /// row (EngineConfig::segment_await_ticks ≠ 0): running with no suspension reason, the
  /// running table's last row written, no approved segment staged (an approve pending for a
  /// staged one counts as approved), no abort or suspend pending, and the wait not ended.
  /// A loop whose peer owns the clock (lock-step) stops ticking while this holds, so the
  /// simulated plant's time stands still; in real time the loop keeps ticking and the
  /// engine holds the baseline. Cyclic path: O(1).
  [[nodiscard]] bool awaiting_segment() const noexcept;

  /// Ends the wait for a segment: the next compute() that finds the running table's end
  /// completes the run (ramp out, baseline confirmed) as without segment_await_ticks. For a
  /// loop that times the wait itself (lock-step: on the real clock). Cyclic path.
  void end_await() noexcept { await_over_ = true; }

  /// A fault found outside the engine (the run log cannot be written, the device refused a
  /// write) stops the excitation at once: armed, running or suspended → aborted (ramp out,
  /// baseline confirmed by readback as after any abort) with outcome `why`. The first fault
  /// names the outcome; later calls and calls in other states change nothing else (a run
  /// already returning keeps returning). Cyclic path: no allocation.
  void fault(Outcome why) noexcept;

  /// Phase 1 of a tick: applies the pending command and the transitions due, advances the
  /// table row while running and returns the setpoints (clamped to [min, max], slew
  /// limited to max_move per tick) with the next heartbeat.
  /// `skipped_ticks`: grid points the clock passed without a tick since the last one (the
  /// loop overran its deadlines). Time is counted on the clock: the tick index (the log's
  /// k) jumps by them, the row is flagged kSkipped, and the suspension timeout and the
  /// unconfirmed window count them as elapsed. The table, the ramp and max_move advance per
  /// tick written (the field only changes when written).
  const TickOutput& compute(std::uint64_t skipped_ticks = 0) noexcept;

  /// Phase 2: the exchange's result. `values` (config.values of them) is read only when
  /// exchange_ok. Checks the heartbeat echo, the test limits and the command register,
  /// and moves the state (suspend, resume after dwell, abort on timeout, safe).
  /// `refused`: the exchange failed because the device refused the request (an exception
  /// reply 1–3): counted as a failed exchange, but the link is fine — the row is not flagged
  /// comm_lost and the comm guard does not count it (the loop calls fault() next).
  void observe(bool exchange_ok, std::span<const double> values, bool refused = false) noexcept;

  /// Between compute() and the write of a tick that follows a failed exchange: `values` were
  /// read on the (re)connected link before anything was written on it. The heartbeat echo
  /// must have moved forward from the last echo seen by at most the heartbeats sent since;
  /// an echo that went backwards or jumped beyond them means the peer restarted or lost its
  /// state: this tick's row is flagged kDiscontinuity (a new segment of plant data).
  void check_peer_continuity(std::span<const double> values) noexcept;

  /// One owner (issue 39 §1), between compute() and the write of a tick on a link without a
  /// failure since the last exchange (else check_peer_continuity): `values` were read before
  /// this tick's write. They must be what this gateway left: each setpoint's readback that
  /// agreed at the last reading must read one of the values written lately (the last
  /// kMaxReadbackLag writes; a lagging peer shows an older one), and the heartbeat echo may
  /// only have moved forward, by at most the heartbeats sent. Otherwise another master wrote
  /// between the two exchanges: foreign_write() names it and this tick's observe() stops the
  /// excitation (Outcome::foreign_writer). Nothing is judged while returning: a write in
  /// flight when the peer froze may land late there, and confirm() undoes it. Cyclic path.
  void check_before_write(std::span<const double> values) noexcept;

  /// The tick just completed, for the run log.
  [[nodiscard]] TickRecord record(std::int64_t time_ns) const noexcept;

  [[nodiscard]] State state() const noexcept { return state_; }
  [[nodiscard]] Outcome outcome() const noexcept { return outcome_; }
  [[nodiscard]] std::uint8_t suspend_reasons() const noexcept { return reasons_; }
  [[nodiscard]] std::uint32_t row() const noexcept { return row_; }
  /// The plan segment streaming: 0 the plan started with, +1 at every switch.
  [[nodiscard]] std::uint32_t segment() const noexcept { return segment_; }
  /// A segment is staged (waiting for approval or for the boundary).
  [[nodiscard]] bool segment_staged() const noexcept { return staged_.data != nullptr; }
  [[nodiscard]] bool segment_approved() const noexcept { return staged_approved_; }
  [[nodiscard]] std::uint64_t ticks() const noexcept { return ticks_; }  // since arm, on the clock
  [[nodiscard]] std::uint64_t skipped_ticks() const noexcept { return skipped_total_; }
  /// Ticks written holding the baseline while awaiting a segment (rows flagged kSuspended
  /// in state running), since arm.
  [[nodiscard]] std::uint64_t awaited_ticks() const noexcept { return awaited_total_; }
  [[nodiscard]] std::uint64_t discontinuities() const noexcept { return discontinuities_; }
  [[nodiscard]] std::uint32_t flags() const noexcept { return flags_; }
  [[nodiscard]] double ramp() const noexcept { return ramp_; }  // 0 … 1
  [[nodiscard]] double baseline(std::uint32_t input) const noexcept { return base_u_[input]; }
  [[nodiscard]] double value_baseline(std::uint32_t value) const noexcept { return base_y_[value]; }
  [[nodiscard]] const TickOutput& output() const noexcept { return out_; }
  [[nodiscard]] const EngineConfig& config() const noexcept { return config_; }
  // Counters over the run (for the summary line and the log's notes).
  [[nodiscard]] std::uint64_t failed_exchanges() const noexcept { return failed_total_; }
  [[nodiscard]] std::uint64_t comm_losses() const noexcept { return comm_losses_; }
  [[nodiscard]] std::uint64_t suspensions() const noexcept { return suspensions_; }
  /// Closed loop: episodes of the controller out of its mode (manual, off, suspended) and of
  /// an MV clamped or wound up, since arm (each counted once, at its first reading).
  [[nodiscard]] std::uint64_t controller_mode_losses() const noexcept { return mode_losses_; }
  [[nodiscard]] std::uint64_t mv_limited_episodes() const noexcept { return mv_limited_; }
  /// Ticks (rows of the run log) that carried `flag` (one runlog::Flag bit), since arm.
  [[nodiscard]] std::uint64_t rows_flagged(std::uint32_t flag) const noexcept;
  [[nodiscard]] std::uint64_t readback_mismatches() const noexcept { return mismatches_total_; }
  [[nodiscard]] const ReadbackFault& readback_fault() const noexcept { return fault_; }
  /// The first write of another master (check_quiet, or while running: the run's outcome is
  /// then Outcome::foreign_writer); not valid when none was seen.
  [[nodiscard]] const ForeignWrite& foreign_write() const noexcept { return foreign_; }
  /// Confirmation (config.confirm_timeout_ticks ≠ 0): episodes in which the device held
  /// another value than the baseline written after the output had reached it — a write
  /// applied late — each undone by the baseline written again.
  [[nodiscard]] std::uint64_t stale_writes_undone() const noexcept { return stale_undone_; }
  /// acknowledge_command: the last reading of the command register was not 0 and it has not
  /// been cleared yet; the Runner writes 0 to it and, when the write succeeded, calls
  /// command_cleared() (the next reading that is not 0 is then a new command).
  [[nodiscard]] bool command_clear_due() const noexcept { return command_clear_due_; }
  void command_cleared() noexcept;
  /// Readings of the command register cleared since arm (each command acted on, and a code
  /// left from before the run).
  [[nodiscard]] std::uint64_t commands_acknowledged() const noexcept { return acknowledged_; }
  /// Whether `read` agrees with `written` for input c (the tolerance of InputLimits).
  [[nodiscard]] bool readback_agrees(std::uint32_t c, double written, double read) const noexcept;

 private:
  void apply_command() noexcept;
  void enter_suspended() noexcept;
  void enter_returning() noexcept;
  // compute()'s parts, in the order it calls them (README "The tick").
  void advance_row() noexcept;
  void switch_segment() noexcept;
  void move_ramp() noexcept;
  void limit_setpoints() noexcept;
  // observe()'s judgement of the state after this tick's checks.
  void judge_suspension() noexcept;
  void judge_return() noexcept;
  void check_comm(bool exchange_ok, std::span<const double> values) noexcept;
  void check_limits(bool exchange_ok, std::span<const double> values) noexcept;
  void read_command_register(bool exchange_ok, std::span<const double> values) noexcept;
  void check_readbacks(std::span<const double> values) noexcept;
  void check_controller(bool exchange_ok, std::span<const double> values) noexcept;
  void foreign_seen(const ForeignWrite& what) noexcept;
  /// Whether `read` agrees with one of input c's last kMaxReadbackLag writes (this tick's
  /// included): a value this gateway wrote lately, whatever the peer's lag.
  [[nodiscard]] bool wrote_lately(std::uint32_t c, double read) const noexcept;
  [[nodiscard]] bool real_time_passed(std::int64_t& since_ns, std::int64_t limit_ns) noexcept;
  [[nodiscard]] bool at_baseline() const noexcept;
  void count_flags() noexcept;
  [[nodiscard]] bool at_segment_boundary() const noexcept;
  void confirm(bool out_at_baseline) noexcept;
  [[nodiscard]] bool hold_for_segment() noexcept;

  EngineConfig config_{};
  signal::ConstTableView table_{};
  State state_ = State::configured;
  Outcome outcome_ = Outcome::none;
  bool configured_ = false;
  bool armed_ = false;  // arm() succeeded: writing is allowed
  Command pending_ = Command::none;
  std::uint8_t reasons_ = 0;

  std::array<double, kMaxInputs> base_u_{};
  std::array<double, kMaxValues> base_y_{};
  std::array<double, kMaxInputs> excitation_{};  // table row in use (frozen when suspended)
  std::array<double, kMaxValues> last_y_{};      // last good values
  TickOutput out_{};
  double ramp_ = 0.0;                // excitation scale, 0 … 1, moves 1/ramp_ticks per tick
  std::uint32_t row_ = 0;            // table row of the current excitation
  std::uint32_t segment_ = 0;        // plan segment of table_
  signal::ConstTableView staged_{};  // the next segment's table; data == nullptr: none
  bool staged_approved_ = false;
  bool awaiting_ = false;      // holding the baseline at the table's end for a segment
  bool await_over_ = false;    // the wait ended (timed out, end_await): complete
  std::uint64_t awaited_ = 0;  // ticks of the clock in the current wait
  std::uint64_t awaited_total_ = 0;
  bool row_started_ = false;   // row_ has been written at least once
  std::uint64_t ticks_ = 0;    // ticks since arm: ticks written + ticks skipped
  std::uint64_t writes_ = 0;   // ticks written since arm (the heartbeat and readback ring)
  std::uint64_t elapsed_ = 1;  // ticks of the clock this tick stands for (1 + skipped)
  std::uint32_t flags_ = 0;    // this tick's runlog flags
  bool exchange_ok_ = false;

  std::uint32_t fail_streak_ = 0;     // failed exchanges in a row
  std::uint32_t comm_ok_streak_ = 0;  // good exchanges in a row while kReasonComm
  std::uint32_t inside_streak_ = 0;   // ticks all inside the hysteresis band
  std::uint64_t suspended_ticks_ = 0;
  std::uint64_t returning_ticks_ = 0;
  bool stale_ = false;
  double last_command_code_ = 0.0;
  bool have_command_code_ = false;
  bool command_clear_due_ = false;
  std::uint64_t acknowledged_ = 0;

  // Verified writes: the setpoints written in the last kMaxReadbackLag ticks (slot
  // tick % kMaxReadbackLag), mismatch streaks, and whether this tick's readings confirmed
  // the baseline (every readback agrees with a written baseline).
  std::array<std::array<double, kMaxInputs>, kMaxReadbackLag> written_{};
  std::array<std::uint32_t, kMaxInputs> mismatch_streak_{};
  bool baseline_read_back_ = false;
  std::uint64_t confirm_ticks_ = 0;  // returning ticks with the output at baseline
  ReadbackFault fault_{};
  std::uint64_t mismatches_total_ = 0;
  bool mismatch_now_ = false;             // this tick, a readback disagreed with what was written
  std::uint64_t confirm_elapsed_ = 0;     // ticks of the clock with the output at the baseline
  bool confirmed_once_ = false;           // the first of the two readbacks happened …
  std::uint64_t first_confirm_tick_ = 0;  // … at this tick
  bool stale_episode_ = false;
  std::uint64_t stale_undone_ = 0;

  // One owner: the readback compared on the last good exchange per setpoint, and whether it
  // agreed (a change away from an unchanged write is another master's).
  std::array<double, kMaxInputs> last_compared_{};
  std::array<bool, kMaxInputs> last_agreed_{};
  ForeignWrite foreign_{};
  bool foreign_now_ = false;  // this tick saw another master's write
  bool previous_ok_ = false;  // the last exchange succeeded (no reconnect since)

  // Timeouts on the real clock (set_real_time; EngineConfig::*_timeout_ns): -1 not started.
  bool real_clock_ = false;
  std::int64_t now_ns_ = 0;
  std::int64_t suspended_since_ns_ = -1;
  std::int64_t confirming_since_ns_ = -1;

  std::uint64_t failed_total_ = 0;
  std::uint64_t skipped_total_ = 0;
  std::uint64_t discontinuities_ = 0;
  std::uint16_t last_echo_ = 0;  // the heartbeat echo of the last good exchange
  bool have_echo_ = false;
  std::array<std::uint64_t, 8> flag_rows_{};  // per runlog flag bit: rows that carried it
  std::uint64_t comm_losses_ = 0;
  std::uint64_t suspensions_ = 0;

  // Closed loop (EngineConfig::controller).
  bool controller_in_mode_ = true;  // the last good reading: mode control or test
  bool mv_limited_now_ = false;     // the last good reading: an MV clamped or wound up
  std::uint32_t controller_ok_streak_ = 0;
  std::uint64_t controller_ticks_ = 0;  // suspended with kReasonController, on the clock
  std::int64_t controller_since_ns_ = -1;
  std::uint64_t mode_losses_ = 0;
  std::uint64_t mv_limited_ = 0;
};

}  // namespace excite::engine
