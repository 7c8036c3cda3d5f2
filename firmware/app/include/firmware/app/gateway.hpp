// SPDX-License-Identifier: MIT
#pragma once
// The gateway in one component: configuration → plan → tables → engine → arm → run → log.
// excite-gateway's main(), the integration fixtures and the benches all build the gateway
// through it; they differ only in the field bus and the clock they hand it (the configured
// transport's bus and the POSIX clock in the field; a simulated plant and a virtual clock in
// tests).
//
//   Gateway gw(config);                      1. a parsed, validated configuration
//   gw.load_plan(bytes, "plans/x.plan");     2.–3. plan decoded, table generated into fixed
//                                                  storage and checked, engine configured
//   gw.arm(bus, clock);                      4. one read of the live values, then the
//                                                  baseline written once and read back
//   gw.start_log(file, "excite-gateway 0.1.0");  5. header written, log thread started
//   gw.run(commands, &stop);                 6. the cyclic loop: allocates nothing
//   gw.finish_log();                         7. drained, flushed, log thread joined
//
// Each start-up stage returns std::nullopt, or the failure with the exit code
// excite-gateway returns for it (README.md) and a message naming what was wrong. Start-up
// allocates and may fail; run() allocates nothing and throws nothing.
//
// Time: the plan's sample time T is in minutes (plan format v2) and stays in minutes into
// the run log (t_min = tick · T); the tick period is T itself, converted once to the
// clock's nanoseconds by std::chrono, unless the configuration's period_s compresses time.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/exit_codes.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/app/log_drain.hpp"
#include "firmware/app/runner.hpp"
#include "firmware/app/segment_inbox.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/engine/log_ring.hpp"
#include "firmware/plan/plan.hpp"
#include "firmware/runlog/writer.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::app {

struct StageError {
  ExitCode code = ExitCode::ok;
  std::string message;  // one line, without the program name
};
using StageResult = std::optional<StageError>;  // nullopt: the stage succeeded

/// The sample time's one unit, minutes; std::chrono converts it to the clock's nanoseconds.
using Minutes = std::chrono::duration<double, std::ratio<60>>;

class Gateway {
 public:
  explicit Gateway(GatewayConfig config);
  ~Gateway();
  Gateway(const Gateway&) = delete;
  Gateway& operator=(const Gateway&) = delete;

  /// 2.–3. Decodes the plan file (its channel count against the setpoints), generates its
  /// table into the fixed storage (signal::kTableCapacity values), checks it against the
  /// plan's limits (bad_plan), and configures the engine (bad_config). `plan_name` is the
  /// run log's `plan:` line.
  StageResult load_plan(std::span<const std::uint8_t> plan_file, std::string plan_name);

  /// 4. Reads the live values through `bus` — twice, a quiet interval apart, with
  /// observe_quiet_on(): refused when another master is writing (one owner) — and arms the
  /// engine on the last reading; then writes the baseline once and reads it back (verified
  /// writes). arm_refused on any failure, naming the setpoint (or the heartbeat echo), what
  /// was written or read first and what came back. bus and clock must outlive the
  /// Gateway's run().
  StageResult arm(hal::FieldBus& bus, hal::Clock& clock);

  /// 5. Writes the run log's header to `file` (the caller's; closed by the caller after
  /// finish_log()) naming `producer`, and starts the log thread (log_error).
  StageResult start_log(std::FILE* file, std::string producer);

  /// 5b. (optional, after arm) Plan segments (README "Plan segments"): allocates the second
  /// table buffer and starts the inbox thread watching `dir`/next.plan; each tick of run()
  /// then stages what it hands over. `allow_distortion`: --allow-distortion.
  void start_segments(std::string dir, bool allow_distortion, std::FILE* events,
                      std::string run_id = {});
  /// Stops the inbox thread (also done by the destructor); the inbox, or null without one.
  void stop_segments();
  [[nodiscard]] const SegmentInbox* segments() const noexcept { return inbox_.get(); }

  /// 6. Runs until the engine is safe, `stop` is raised or max_ticks have run (0: no limit).
  RunStats run(CommandMailbox& commands, const std::atomic<bool>* stop = nullptr,
               std::uint64_t max_ticks = 0) noexcept;

  /// 7. Drains what is left, joins the log thread; the first write error, if any.
  runlog::WriteStatus finish_log();

  // ---- what start-up produced (valid after load_plan) ----
  [[nodiscard]] const GatewayConfig& config() const noexcept { return config_; }
  [[nodiscard]] const plan::Plan& plan() const noexcept { return *plan_; }
  /// The table of the plan started with (segment 0). With plan segments its storage is
  /// reused by segments 2, 4, … once the engine has left it: read it before run().
  [[nodiscard]] signal::ConstTableView table() const noexcept { return table_; }
  [[nodiscard]] const engine::EngineConfig& engine_config() const noexcept {
    return engine_config_;
  }
  [[nodiscard]] Minutes sample_time() const noexcept { return sample_time_; }
  [[nodiscard]] hal::Nanoseconds period() const noexcept { return period_; }
  [[nodiscard]] const engine::Engine& engine() const noexcept { return *engine_; }
  [[nodiscard]] std::uint64_t rows_logged() const noexcept;
  /// Why the run log could not be written (LogDrain::failure(), after finish_log()); "" if
  /// every write succeeded. A failure mid-run stopped the excitation (Outcome::log_fault).
  [[nodiscard]] std::string log_failure() const;
  /// The log ring (valid after arm), for a caller that drains it on its own thread instead
  /// of start_log() (the no-allocation proof, the benches).
  [[nodiscard]] engine::LogRingBase& log_ring() noexcept { return *ring_; }

  /// Readings at the end of their encoding's range, per value (hal::CarriedRange).
  [[nodiscard]] std::span<const std::uint64_t> readings_at_range_end() const noexcept {
    return {range_end_counts_.data(), config_.values.size()};
  }
  /// Another master's write in words (Engine::foreign_write()): "setpoint u1 (register 100
  /// float32 ABCD) = 0.057 read back from u1_sp at tick 52, expected 0.078 …"; "" when none.
  [[nodiscard]] std::string foreign_write_report() const;
  /// "xD 101 readings (register 200 uint16 raw 0..65535 = 0..1)"; "" when there were none.
  [[nodiscard]] std::string range_end_report() const;
  /// The device's refusal in words (Runner::refusal()): "device refused setpoint u1 = 0.2165
  /// (register 100 float32 ABCD) at tick 12: exception 3, illegal data value — the device's
  /// own limits?"; several setpoints when one request carried them; "" when there was none.
  [[nodiscard]] std::string refusal_report() const;
  /// The engine's readback fault in words: "setpoint u1 (register 100 float32 CDAB): wrote
  /// 0.5, read back 3.2e-41 from u1_rb at tick 12"; "" when there was none.
  [[nodiscard]] std::string readback_fault_report() const;

  // ---- hooks (tests and benches) ----
  void set_observer(TickObserver* observer) noexcept { observer_ = observer; }
  void set_lateness_histogram(std::span<std::uint64_t> bins_us) noexcept { lateness_ = bins_us; }
  void set_event_stream(std::FILE* events) noexcept { events_ = events; }
  void set_row_delay(std::chrono::microseconds delay) noexcept { row_delay_ = delay; }
  /// Before arm(): false skips writing the baseline at arm (a lock-step simulated plant takes
  /// one sample per heartbeat, so that write would shift the run by one sample); the
  /// cyclic readback check still applies from the first tick.
  void set_verify_at_arm(bool on) noexcept { verify_at_arm_ = on; }
  /// Before run(): with [segments] await_s > 0, awaits a segment without ticking, timed on
  /// `real` (Runner::await_segments_on; lock-step). null (the default): the engine holds the
  /// baseline, ticking (real time).
  void await_segments_on(hal::Clock* real) noexcept { await_clock_ = real; }
  /// Before arm(): one owner (Runner::observe_quiet) — the live values read twice,
  /// quiet_interval() apart on `real`. null (the default): one read.
  void observe_quiet_on(hal::Clock* real, hal::Nanoseconds interval) noexcept {
    quiet_clock_ = real;
    quiet_interval_ = interval;
  }
  /// The quiet interval observed before arm: long enough to see a master that writes at this
  /// gateway's pace (a second gateway with the same configuration) — 100 ms in lock-step
  /// (such a master writes every few milliseconds), one period + 100 ms in real time (it
  /// writes once per period).
  [[nodiscard]] hal::Nanoseconds quiet_interval(bool lockstep) const;
  /// Before run(): Runner::read_before_write (one owner; real time).
  void read_before_write(bool on) noexcept { read_before_write_ = on; }
  /// Before run(): Runner::time_on_real_clock (lock-step: the suspension and confirmation
  /// timeouts on `real`).
  void time_on_real_clock(hal::Clock* real) noexcept { real_time_ = real; }
  /// Before run(): Runner::pace_retries (lock-step: retries after a failure on `real`, at
  /// most one per `interval`).
  void pace_retries(hal::Clock* real, hal::Nanoseconds interval) noexcept {
    pacing_clock_ = real;
    retry_interval_ = interval;
  }

 private:
  GatewayConfig config_;
  std::unique_ptr<plan::Plan> plan_;
  std::vector<double> storage_;        // the gateway's fixed table storage
  std::vector<double> spare_storage_;  // the second, for plan segments (start_segments)
  std::unique_ptr<SegmentInbox> inbox_;
  signal::TableView table_;
  engine::EngineConfig engine_config_;
  std::unique_ptr<engine::Engine> engine_;
  Minutes sample_time_{0.0};
  hal::Nanoseconds period_{0};
  std::vector<engine::TickRecord> ring_storage_;
  std::unique_ptr<engine::SpanLogRing> ring_;
  std::unique_ptr<Runner> runner_;
  std::array<RangeEnd, engine::kMaxValues> range_ends_{};
  std::array<std::uint64_t, engine::kMaxValues> range_end_counts_{};
  std::vector<std::string> range_what_;
  // The run log: the strings its header points into live here.
  std::string plan_name_;
  std::string producer_;
  std::vector<runlog::Channel> inputs_;
  std::vector<runlog::Channel> outputs_;
  std::unique_ptr<LogDrain> drain_;
  TickObserver* observer_ = nullptr;
  hal::Clock* await_clock_ = nullptr;
  std::span<std::uint64_t> lateness_{};
  std::FILE* events_ = nullptr;
  std::chrono::microseconds row_delay_{0};
  bool verify_at_arm_ = true;
  hal::Clock* pacing_clock_ = nullptr;
  hal::Nanoseconds retry_interval_{0};
  hal::Clock* real_time_ = nullptr;
  bool read_before_write_ = false;
  hal::Clock* quiet_clock_ = nullptr;
  hal::Nanoseconds quiet_interval_{0};
};

}  // namespace excite::app
