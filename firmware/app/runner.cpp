// SPDX-License-Identifier: MIT
#include "firmware/app/runner.hpp"

#include "excite/hal/periodic.hpp"

namespace excite::app {

engine::Status Runner::arm() noexcept {
  const std::uint32_t n = engine_.config().values;
  if (bus_.value_count() != n || bus_.setpoint_count() != engine_.config().inputs) {
    return engine::Status::error(
        engine::StatusCode::invalid_field, "field bus = %zu setpoints, %zu values, expected %u, %u",
        bus_.setpoint_count(), bus_.value_count(), engine_.config().inputs, n);
  }
  hal::StatusCode s = bus_.read(std::span<double>(values_.data(), n));
  if (s != hal::StatusCode::ok) {
    return engine::Status::error(engine::StatusCode::invalid_field,
                                 "first read of the live values = %s (%s), expected ok",
                                 hal::to_string(s), bus_.detail());
  }
  if (quiet_clock_ != nullptr) {  // one owner: the same values a quiet interval later
    const std::array<double, engine::kMaxValues> first = values_;
    quiet_clock_->sleep_until(quiet_clock_->now() + quiet_interval_);
    s = bus_.read(std::span<double>(values_.data(), n));
    if (s != hal::StatusCode::ok) {
      return engine::Status::error(engine::StatusCode::invalid_field,
                                   "second read of the live values = %s (%s), expected ok",
                                   hal::to_string(s), bus_.detail());
    }
    if (auto q = engine_.check_quiet(std::span<const double>(first.data(), n),
                                     std::span<const double>(values_.data(), n));
        !q) {
      return q;
    }
  }
  if (auto a = engine_.arm(std::span<const double>(values_.data(), n)); !a) return a;
  if (!engine_.config().verify_readbacks || !verify_at_arm_) return {};
  // Verified writes at arm: write the baseline once (heartbeat 0; the first tick writes 1),
  // read it back, and refuse before any excitation when a readback disagrees.
  const engine::TickOutput& out = engine_.output();
  hal::StatusCode w = bus_.write(out.setpoints(), 0);
  if (w == hal::StatusCode::ok) w = bus_.read(std::span<double>(values_.data(), n));
  if (w != hal::StatusCode::ok) {
    return engine::Status::error(engine::StatusCode::invalid_field,
                                 "writing the baseline and reading it back = %s (%s), expected ok",
                                 hal::to_string(w), bus_.detail());
  }
  return engine_.verify_arm(std::span<const double>(values_.data(), n));
}

void Runner::stage_published() noexcept {
  if (segments_ == nullptr) return;
  const std::uint32_t id = segments_->published.load(std::memory_order_acquire);
  if (id == segment_seen_) return;
  segment_seen_ = id;
  if (!engine_.stage(segments_->table, segments_->approved)) {
    segments_->stage_refused.store(true, std::memory_order_release);
  }
}

// False when `stop` was raised while waiting.
bool Runner::await_segment(CommandMailbox& commands, const std::atomic<bool>* stop) noexcept {
  if (await_clock_ == nullptr || !engine_.awaiting_segment()) return true;
  const hal::Nanoseconds from = await_clock_->now();
  ++segment_waits_;
  bool stopped = false;
  while (engine_.awaiting_segment()) {
    if (stop != nullptr && stop->load(std::memory_order_acquire)) {
      stopped = true;
      break;
    }
    const hal::Nanoseconds now = await_clock_->now();
    if (now - from >= await_limit_) {
      engine_.end_await();
      break;
    }
    stage_published();
    const engine::Command c = commands.take();
    if (c == engine::Command::approve && !engine_.segment_staged()) continue;
    if (c != engine::Command::none) engine_.command(c);
    if (engine_.awaiting_segment()) await_clock_->sleep_until(now + std::chrono::milliseconds(1));
  }
  const hal::Nanoseconds waited = await_clock_->now() - from;
  segment_wait_ += waited;
  if (waited > longest_wait_) longest_wait_ = waited;
  return !stopped;
}

void Runner::tick(std::int64_t time_ns, engine::Command command, std::uint64_t skipped) noexcept {
  if (real_time_ != nullptr) engine_.set_real_time(real_time_->now().count());
  if (command != engine::Command::none) engine_.command(command);
  stage_published();
  const engine::TickOutput& out = engine_.compute(skipped);
  if (segments_ != nullptr) segments_->running.store(engine_.segment(), std::memory_order_release);
  const std::uint32_t n = engine_.config().values;
  const std::span<double> values(values_.data(), n);
  bool ok = false;
  bool refused = false;
  if (out.write) {
    last_status_ = hal::StatusCode::ok;
    if (reverify_) {  // after a failure: read the peer before writing anything to it again
      ++reverified_;
      last_status_ = bus_.read(values);
      if (last_status_ == hal::StatusCode::ok) engine_.check_peer_continuity(values);
    } else if (read_before_write_) {  // one owner: nobody else wrote since the last tick
      last_status_ = bus_.read(values);
      if (last_status_ == hal::StatusCode::ok) engine_.check_before_write(values);
    }
    if (last_status_ == hal::StatusCode::ok)
      last_status_ = bus_.write(out.setpoints(), out.heartbeat);
    if (last_status_ == hal::StatusCode::ok) last_status_ = bus_.read(values);
    ok = last_status_ == hal::StatusCode::ok;
    reverify_ = !ok;
    if (!ok && pacing_clock_ != nullptr) last_failed_at_ = pacing_clock_->now();
    // The device refused the request itself (it will again): not a link fault. The first
    // refusal is kept and stops the excitation below; other peer errors stay with the comm
    // guard.
    if (last_status_ == hal::StatusCode::peer_error && !refusal_.valid) {
      const hal::PeerRefusal e = bus_.last_refusal();
      if (e.valid) {
        refusal_.valid = true;
        refusal_.peer = e;
        refusal_.tick = engine_.ticks() == 0 ? 0 : engine_.ticks() - 1;
        refusal_.setpoint = out.setpoint;
        refused = true;
      }
    }
  }
  if (ok) {
    for (std::size_t j = 0; j < range_ends_.size() && j < n; ++j) {
      const RangeEnd& e = range_ends_[j];
      if (e.watched && (values[j] <= e.low || values[j] >= e.high)) ++range_counts_[j];
    }
  }
  engine_.observe(ok, values, refused);
  if (ok && engine_.command_clear_due()) acknowledge_command();
  // After observe(), so this tick's row says `aborted`: the ramp-out starts next tick.
  if (refused) engine_.fault(engine::Outcome::device_refused);
  if (log_failed_ != nullptr && log_failed_->load(std::memory_order_acquire)) {
    engine_.fault(engine::Outcome::log_fault);
  }
  if (out.write) ring_.push(engine_.record(time_ns));
  ++ticks_;
}

// The command register's acknowledgement: 0 written back after a command was read, so the
// operator's next code is a new edge even when it is the same code (issue 39 §3). A failed
// clear is counted and tried again after the next reading; it is not an exchange failure.
void Runner::acknowledge_command() noexcept {
  const auto index = static_cast<std::size_t>(engine_.config().command_value);
  if (bus_.write_value(index, 0.0) == hal::StatusCode::ok) {
    engine_.command_cleared();
  } else {
    ++command_clear_failures_;
  }
}

RunStats Runner::run(CommandMailbox& commands, const std::atomic<bool>* stop,
                     std::uint64_t max_ticks) noexcept {
  hal::PeriodicSchedule schedule(clock_, period_);
  RunStats stats;
  const std::uint64_t first = ticks_;
  while (true) {
    if (stop != nullptr && stop->load(std::memory_order_acquire)) break;
    if (max_ticks != 0 && ticks_ - first >= max_ticks) break;
    if (!await_segment(commands, stop)) break;
    const std::uint64_t overruns_before = schedule.overruns();
    const hal::Nanoseconds nominal = schedule.wait_next();
    const std::uint64_t skipped = schedule.overruns() - overruns_before;
    if (!lateness_.empty()) {
      const auto late_us = (clock_.now() - nominal).count() / 1000;
      const auto last = lateness_.size() - 1;
      const auto bin = late_us < 0 ? 0U : static_cast<std::size_t>(late_us);
      ++lateness_[bin < last ? bin : last];
    }
    if (pacing_clock_ != nullptr && reverify_) {  // the last exchange failed: pace the retry
      const hal::Nanoseconds due = last_failed_at_ + retry_interval_;
      if (pacing_clock_->now() < due) {
        ++paced_;
        pacing_clock_->sleep_until(due);
      }
    }
    tick(nominal.count(), commands.take(), skipped);
    if (observer_ != nullptr) observer_->after_tick(engine_, ticks_ - 1);
    if (engine::finished(engine_.state())) break;
  }
  stats.ticks = ticks_ - first;
  stats.schedule_overruns = schedule.overruns();
  stats.failed_exchanges = engine_.failed_exchanges();
  stats.ring_overruns = ring_.overruns();
  stats.reverified = reverified_;
  stats.command_clear_failures = command_clear_failures_;
  stats.paced = paced_;
  stats.segment_waits = segment_waits_;
  stats.segment_wait = segment_wait_;
  stats.longest_segment_wait = longest_wait_;
  stats.final_state = engine_.state();
  stats.outcome = engine_.outcome();
  return stats;
}

}  // namespace excite::app
