// SPDX-License-Identifier: MIT
#pragma once
// The gateway's cyclic loop: the engine (pure) wired to a field bus and a clock.
//
//   every period:  wait for the grid point (PeriodicSchedule, absolute deadline)
//                  take an operator command; compute; write + read on the bus;
//                  observe; push the tick's record into the log ring
//
// Reconnect hygiene: after a failed exchange (the hal closed the link: a late reply is never
// taken for a new one) the next tick first reads on the (re)connected link and writes only
// when that read succeeded; the read checks the peer's heartbeat echo for a restart
// (Engine::check_peer_continuity → kDiscontinuity).
//
// until the engine is finished (safe or safe_unconfirmed; that tick is logged), max_ticks
// have run, or `stop` is raised (hard stop: no ramp-out; SIGTERM posts abort instead).
// run() allocates nothing, throws nothing and blocks on nothing but the bus and the
// clock (proved by tests/integration/engine/no_alloc_test).

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>

#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/segment_handoff.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/engine/log_ring.hpp"

namespace excite::app {

/// The retry pacing in lock-step (issue 39 §2): after a failed exchange the next one waits
/// this long on the real clock — never the period, which is the plant's time, standing
/// still while exchanges fail. Operator commands and signals are taken at every tick, so
/// they act within it.
inline constexpr hal::Nanoseconds kRetryPacing = std::chrono::milliseconds(250);

struct RunStats {
  std::uint64_t ticks = 0;              // ticks executed
  std::uint64_t schedule_overruns = 0;  // grid points skipped because a tick ran late (the
                                        // log's k jumps over them; rows flagged skipped)
  std::uint64_t failed_exchanges = 0;
  std::uint64_t ring_overruns = 0;  // records dropped because the log ring was full
  std::uint64_t reverified = 0;     // ticks after a failed exchange that read the peer first
  std::uint64_t paced = 0;          // retries held back by the retry pacing (pace_retries)
  std::uint64_t command_clear_failures = 0;  // acknowledgements of the command register whose
                                             // write failed (tried again on the next tick)
  std::uint64_t segment_waits = 0;           // times the loop stopped ticking to await a segment
                                             // (await_segments_on)
  hal::Nanoseconds segment_wait{0};          // how long, in all, on the real clock
  hal::Nanoseconds longest_segment_wait{0};
  engine::State final_state = engine::State::configured;
  engine::Outcome outcome = engine::Outcome::none;
};

/// The first request the device refused (hal::PeerRefusal): what was being written, at which
/// tick. Found on the cyclic path (fixed storage).
struct Refusal {
  bool valid = false;
  hal::PeerRefusal peer{};
  std::uint64_t tick = 0;                             // the engine's tick of the refused exchange
  std::array<double, engine::kMaxInputs> setpoint{};  // the setpoints written (a write)
};

/// A value's watched range end: a good reading ≤ low or ≥ high is counted (the reading may
/// have been clipped by its encoding; hal::CarriedRange). Not watched: never counted.
struct RangeEnd {
  bool watched = false;
  double low = 0.0;
  double high = 0.0;
};

/// Optional per-tick observer (tests: inject faults at a given tick; bench: nothing).
/// Called after the record is pushed; must not allocate.
class TickObserver {
 public:
  virtual ~TickObserver() = default;
  virtual void after_tick(const engine::Engine& engine, std::uint64_t tick) noexcept = 0;
};

class Runner {
 public:
  Runner(engine::Engine& engine, hal::FieldBus& bus, hal::Clock& clock, engine::LogRingBase& ring,
         hal::Nanoseconds period) noexcept
      : engine_(engine), bus_(bus), clock_(clock), ring_(ring), period_(period) {}

  void set_observer(TickObserver* observer) noexcept { observer_ = observer; }

  /// Histogram of tick lateness (start of the tick's work − its grid point), one bin per
  /// microsecond, the last bin collecting everything later. Empty span: not measured.
  void set_lateness_histogram(std::span<std::uint64_t> bins_us) noexcept { lateness_ = bins_us; }

  /// Counts, per value, good readings at the end of their range (both spans of size
  /// config().values, owned by the caller). Empty: nothing watched.
  void watch_range_ends(std::span<const RangeEnd> ends, std::span<std::uint64_t> counts) noexcept {
    range_ends_ = ends;
    range_counts_ = counts;
  }

  /// A flag the log thread raises when the run log cannot be written (LogDrain::failed()):
  /// the tick that sees it stops the excitation (Engine::fault(Outcome::log_fault): aborted,
  /// ramp out, baseline confirmed). One atomic load per tick; null: not watched.
  void watch_log(const std::atomic<bool>* failed) noexcept { log_failed_ = failed; }

  /// Paced retries (issue 28): after a failed exchange the next tick waits, on `real`, until
  /// `interval` after that failure. For lock-step, where the tick clock never sleeps: a
  /// peer that answers every request at once with an error (a busy device, exception 4/6;
  /// connection refused) is retried a few times a second, not thousands, and the log grows
  /// by as few rows. null: no pacing (the tick clock's period paces in real time).
  void pace_retries(hal::Clock* real, hal::Nanoseconds interval) noexcept {
    pacing_clock_ = real;
    retry_interval_ = interval;
  }

  /// Plan segments (segment_handoff.hpp): each tick stages a newly published segment into
  /// the engine and stores the engine's segment id back. Two atomic loads, one store per
  /// tick; null: no segments.
  void watch_segments(SegmentHandoff* handoff) noexcept { segments_ = handoff; }

  /// Awaiting a segment without ticking (lock-step, README "Plan segments"): while the engine
  /// awaits the next segment (Engine::awaiting_segment) run() does not tick — the peer's
  /// time stands still — but every millisecond on `real` stages a segment the inbox
  /// published and takes operator commands (an approve with nothing staged is dropped, as
  /// the engine would), until a segment is approved, an abort or suspend is posted, `stop`
  /// is raised, or `limit` has passed (then Engine::end_await(): the run completes with its
  /// ramp-out). null: no such wait (real time: the engine holds the baseline, ticking).
  void await_segments_on(hal::Clock* real, hal::Nanoseconds limit) noexcept {
    await_clock_ = real;
    await_limit_ = limit;
  }

  /// Timeouts on the real clock (lock-step, issue 39 §2): each tick hands the engine
  /// `real`'s time (Engine::set_real_time), so the suspension timeout and the confirmation
  /// time end on the real clock at the latest. null: ticks only (real time: the tick clock
  /// is the real clock).
  void time_on_real_clock(hal::Clock* real) noexcept { real_time_ = real; }

  /// One owner (issue 39 §1): arm() reads the live values twice, `interval` apart on `real`,
  /// writing nothing between, and refuses when a setpoint's readback or the heartbeat echo
  /// changed (Engine::check_quiet): it arms on the second reading, one it observed quiet.
  /// null: one read (the in-process tests, whose plant has no other master).
  void observe_quiet(hal::Clock* real, hal::Nanoseconds interval) noexcept {
    quiet_clock_ = real;
    quiet_interval_ = interval;
  }

  /// One owner (issue 39 §1): read the values before every write too, not only after a
  /// failed exchange, so that another master's write between two ticks is seen
  /// (Engine::check_before_write). One more read per tick; real time only — in lock-step a
  /// read with no heartbeat sent would wait for an echo that does not come (CAN), and
  /// arm's quiet interval and the reading after each write watch there.
  void read_before_write(bool on) noexcept { read_before_write_ = on; }

  /// Whether arm() writes the baseline once and reads it back (default true). Off only for
  /// a lock-step simulated peer, where that write would be a plant sample of its own.
  void set_verify_at_arm(bool on) noexcept { verify_at_arm_ = on; }

  /// Reads the live values (twice, a quiet interval apart: observe_quiet) and arms the engine
  /// with them; then (verified writes)
  /// writes the baseline once, reads it back and refuses when a readback disagrees
  /// (Engine::verify_arm; the engine is left configured and names the setpoint).
  engine::Status arm() noexcept;

  RunStats run(CommandMailbox& commands, const std::atomic<bool>* stop = nullptr,
               std::uint64_t max_ticks = 0) noexcept;

  /// One tick at nominal time `time_ns` (run() calls it on the grid), `skipped` grid points
  /// after the previous one was due (Engine::compute: time is counted on the clock).
  void tick(std::int64_t time_ns, engine::Command command, std::uint64_t skipped = 0) noexcept;

  [[nodiscard]] hal::StatusCode last_status() const noexcept { return last_status_; }
  /// The first refusal (exception 1, 2 or 3) of the run; it stopped the excitation
  /// (Engine::fault(Outcome::device_refused)). Not valid when there was none.
  [[nodiscard]] const Refusal& refusal() const noexcept { return refusal_; }

 private:
  void acknowledge_command() noexcept;
  void stage_published() noexcept;
  bool await_segment(CommandMailbox& commands, const std::atomic<bool>* stop) noexcept;

  engine::Engine& engine_;
  hal::FieldBus& bus_;
  hal::Clock& clock_;
  engine::LogRingBase& ring_;
  hal::Nanoseconds period_;
  TickObserver* observer_ = nullptr;
  const std::atomic<bool>* log_failed_ = nullptr;
  SegmentHandoff* segments_ = nullptr;
  std::uint32_t segment_seen_ = 0;  // the last published segment handed to the engine
  hal::Clock* await_clock_ = nullptr;
  hal::Nanoseconds await_limit_{0};
  std::uint64_t segment_waits_ = 0;
  hal::Nanoseconds segment_wait_{0};
  hal::Nanoseconds longest_wait_{0};
  std::span<std::uint64_t> lateness_{};
  std::span<const RangeEnd> range_ends_{};
  std::span<std::uint64_t> range_counts_{};
  std::array<double, engine::kMaxValues> values_{};
  hal::StatusCode last_status_ = hal::StatusCode::ok;
  std::uint64_t ticks_ = 0;
  bool verify_at_arm_ = true;
  bool read_before_write_ = false;
  Refusal refusal_{};
  hal::Clock* pacing_clock_ = nullptr;
  hal::Clock* real_time_ = nullptr;
  hal::Clock* quiet_clock_ = nullptr;
  hal::Nanoseconds quiet_interval_{0};
  hal::Nanoseconds retry_interval_{0};
  hal::Nanoseconds last_failed_at_{0};
  std::uint64_t paced_ = 0;
  bool reverify_ = false;  // the last exchange failed: read before writing again
  std::uint64_t reverified_ = 0;
  std::uint64_t command_clear_failures_ = 0;
};

}  // namespace excite::app
